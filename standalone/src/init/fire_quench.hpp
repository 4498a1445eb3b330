#pragma once
//! Removes overlaps between equal spheres by a soft-sphere quench.
//!
//! The spheres' diameter is inflated by a factor 1 + eps and FIRE (Bitzek et al. 2006; FIRE 2.0
//! step order, Guenole et al. 2020) minimises the harmonic overlap energy 1/2 sum (sigma' - r)^2
//! over overlapping pairs, plus 1/2 sum (r' - h)^2 over spheres closer than r' to a wall, on a
//! cell-grid pair list with a skin (O(N) per iteration). Below jamming the energy can reach
//! zero; the quench stops as soon as no overlap at the inflated size exceeds eps/2 radii, so the
//! true spheres end at least eps/2 diameters apart and eps/2 radii from the walls.
#include <cstdint>
#include <vector>

#include "hardsphere/box.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere {

struct QuenchConfig {
  double inflation = 0.002;             //!< eps: relative diameter inflation
  std::int64_t max_iterations = 10000;  //!< FIRE steps before giving up
};

struct QuenchStats {
  std::int64_t iterations = 0;   //!< FIRE steps taken (summed over calls)
  std::int64_t list_builds = 0;  //!< pair-list builds (summed over calls)
  double energy = 0;             //!< overlap energy left by the last call
  bool jammed = false;           //!< the last call stopped at a force minimum with overlaps left
};

//! Moves the centres x (overlapping or not; spheres of the given radius) until they keep the
//! gaps above. Returns false if the quench jams or runs out of iterations; x then holds the
//! last state. The spheres come back renumbered (they are interchangeable); deterministic.
bool separate_spheres(const Box& box, std::vector<Vec3d>& x, double radius, const QuenchConfig& cfg = {},
                      QuenchStats* stats = nullptr);

}  // namespace hardsphere
