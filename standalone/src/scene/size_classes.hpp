#pragma once
//! Which spheres the cell grid is sized for and which are "big": a grid sized by the largest
//! sphere makes every cell as wide as it, so a few big spheres would slow every small one.
//! Both engines size their grid by SizeSplit::grid_diameter and find the big spheres' partners
//! in a separate pass (every cell a big sphere's reach overlaps, and big against big).
#include <cstdint>
#include <vector>

#include "hardsphere/particles.hpp"

namespace hardsphere {

struct SizeSplit {
  double grid_diameter = 0;        //!< largest diameter of the spheres that are not big
  std::vector<std::uint32_t> big;  //!< input indices of the big spheres, largest first
};

//! The split for these spheres (kBigOverMedian, kMaxBigSpheres in particles.hpp); no big spheres
//! when none exceeds kBigOverMedian medians.
SizeSplit split_by_size(const ParticleSystem& sys);

}  // namespace hardsphere
