#pragma once
//! Sites for the lattice route: at least n sphere centres inside the box, spread evenly.
#include <cstdint>
#include <vector>

#include "hardsphere/box.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere {

struct LatticeSites {
  std::vector<Vec3d> pos;  //!< at least n sites; wall axes keep them within [lo + radius, hi - radius]
  double spacing = 0;      //!< smallest distance between two sites (minimum image); +inf for one site
};

//! An FCC lattice (4 sites per cell), or a plain grid when the box is too thin along two axes
//! for FCC cells (one layer of cells puts two sites on one line): whichever spaces the sites
//! wider. Layers are added one at a time along the axis with the widest spacing, so the site
//! count is the first above n and the work is O(n) for any box.
LatticeSites lattice_sites(const Box& box, std::int64_t n, double radius);

}  // namespace hardsphere
