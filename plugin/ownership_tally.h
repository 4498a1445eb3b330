#pragma once
//! The owned + ghost path's collision totals. Each rank's stepper holds its owned atoms and ghost
//! copies of other ranks' atoms; a collision counts (owned_i + owned_j) / 2 and a wall bounce
//! owned_i, so the ranks' sums add up to one stepper's totals. It also flags the ghosts that met
//! an owned atom in a step: the owner check compares those copies with their owners.
#include <array>
#include <cstdint>
#include <vector>

#include "hardsphere/collision_totals.hpp"
#include "hardsphere/state_exchange.hpp"

namespace LAMMPS_NS {

class OwnershipTally : public hardsphere::CollisionObserver {
 public:
  using Totals = hardsphere::WeightedCollisionTotals;  //!< weighted collisions, walls and virial
  //! A new engine: owned[k] (1 = owned) for its slot k; the totals start from zero.
  void reset(std::vector<std::uint8_t> owned) {
    owned_ = std::move(owned);
    met_.assign(owned_.size(), 0);
    totals_ = Totals{};
  }
  //! Forgets which ghosts met an owned atom (before each step).
  void start_step() { std::fill(met_.begin(), met_.end(), std::uint8_t(0)); }
  const Totals &totals() const { return totals_; }
  //! Whether the sphere in `slot` is a ghost that collided with an owned atom since start_step().
  bool met_owned(std::uint32_t slot) const { return met_[slot] != 0; }

  void collision(std::uint32_t i, std::uint32_t j, const double *tensor, double virial) override {
    const double w = 0.5 * (double(owned_[i]) + double(owned_[j]));
    if (w == 0.5) met_[owned_[i] ? j : i] = 1;
    totals_.collisions += w;
    totals_.pair_virial += w * virial;
    for (std::size_t k = 0; k < 6; k++) totals_.pair_virial_tensor[k] += w * tensor[k];
  }
  void bounce(std::uint32_t i) override { totals_.wall_collisions += double(owned_[i]); }
  void reordered(const std::uint32_t *old, std::size_t n) override {
    for (auto *v : {&owned_, &met_}) {
      scratch_.resize(n);
      for (std::size_t k = 0; k < n; k++) scratch_[k] = (*v)[old[k]];
      v->swap(scratch_);
    }
  }

 private:
  std::vector<std::uint8_t> owned_, met_, scratch_;  // slot order
  Totals totals_;
};

}  // namespace LAMMPS_NS
