#pragma once
//! The arithmetic an engine computes in, and the rounding its states may carry: the stepper runs in
//! double or float, the event engine in double.
#include <limits>

namespace hardsphere {

enum class Precision { Double, Float };
//! Machine epsilon of an engine's arithmetic: the states it writes may hold overlaps up to
//! overlap_tolerance(sys, rounding_epsilon(p)), which every face reading them accepts.
inline double rounding_epsilon(Precision p) {
  return p == Precision::Float ? double(std::numeric_limits<float>::epsilon()) : std::numeric_limits<double>::epsilon();
}

}  // namespace hardsphere
