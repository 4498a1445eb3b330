#pragma once
//! Angular velocities of smooth spheres. No smooth collision changes them, so the stepper carries
//! them unchanged, in double and by id rank, outside every loop of a step, and hands them back in
//! its state bit for bit. Empty while every spin is +0 (the usual smooth scene costs nothing).
#include <cmath>
#include <cstddef>
#include <vector>

#include "hardsphere/vec3.hpp"

namespace hardsphere::detail {

class SmoothSpins {
 public:
  //! The spins of `omega` (input order; shorter means zeros) by id rank: rank r is input
  //! index by_id[r].
  void take(const std::vector<Vec3d>& omega, const std::vector<std::size_t>& by_id) {
    spins_.clear();
    for (std::size_t r = 0; r < by_id.size(); ++r)
      if (by_id[r] < omega.size()) set(r, omega[by_id[r]], by_id.size());
  }
  Vec3d at(std::size_t rank) const { return spins_.empty() ? Vec3d{} : spins_[rank]; }
  //! Sets the spin of id rank `rank` of `n` spheres.
  void set(std::size_t rank, Vec3d w, std::size_t n) {
    if (spins_.empty()) {
      if (!nonzero(w)) return;
      spins_.assign(n, Vec3d{});
    }
    spins_[rank] = w;
  }

 private:
  //! -0 is kept as given too: a spin is copied bit for bit.
  static bool nonzero(Vec3d w) {
    return w.x != 0 || w.y != 0 || w.z != 0 || std::signbit(w.x) || std::signbit(w.y) || std::signbit(w.z);
  }
  std::vector<Vec3d> spins_;
};

}  // namespace hardsphere::detail
