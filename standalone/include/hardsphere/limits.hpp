#pragma once
//! Input limits shared by the data-file reader and the command line, so a count is refused
//! where it is read, before anything is allocated for it.
#include <cstdint>

#include "hardsphere/neighbour_entry.hpp"

namespace hardsphere {

//! The largest system the engines accept: neighbour-list entries hold partner indices up to
//! kMaxAdjIndex (2^27 spheres).
constexpr std::int64_t kMaxSpheres = std::int64_t(kMaxAdjIndex) + 1;

//! Data-file lines are short; a longer one is not a data file (e.g. /dev/zero or a binary).
constexpr std::size_t kMaxDataLine = 65536;

}  // namespace hardsphere
