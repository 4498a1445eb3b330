#pragma once
//! The largest single heap request made while a probe is alive (this test binary replaces the
//! global operator new to watch them), so a test can assert that no allocation was sized from an
//! untrusted count.
#include <cstddef>

namespace test {

class LargestAllocation {
 public:
  LargestAllocation();
  ~LargestAllocation();
  LargestAllocation(const LargestAllocation&) = delete;
  LargestAllocation& operator=(const LargestAllocation&) = delete;
  std::size_t bytes() const;
};

}  // namespace test
