#pragma once
//! Input limits shared by the data-file reader and the command line, so a count is refused
//! where it is read, before anything is allocated for it.
#include <cstddef>
#include <cstdint>

namespace hardsphere {

//! The largest system the engines accept: neighbour-list entries pack a partner index into 27
//! bits (neighbour_entry.hpp checks that the two agree).
constexpr std::int64_t kMaxSpheres = std::int64_t(1) << 27;

//! Data-file lines are short; a longer one is not a data file (e.g. /dev/zero or a binary).
constexpr std::size_t kMaxDataLine = 65536;

}  // namespace hardsphere
