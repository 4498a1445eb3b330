//! The fixed-step engine's rebuild: spheres wrapped into the box, sorted by cell with every
//! per-sphere array permuted alike, and the candidate pair list built afresh.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>

#include "stepper/stepper_engine.hpp"

namespace hardsphere::detail {

template <class Real, bool Mono>
void Stepper<Real, Mono>::rebuild() {
  const std::size_t n = pos_.size();
  const Real lo[3] = {Real(box_.lo[0]), Real(box_.lo[1]), Real(box_.lo[2])};
  for (int d = 0; d < 3; ++d)
    if (unreached_walls_[std::size_t(d)])
      for (std::size_t i = 0; i < n; ++i)
        if (!(pos_[i][d] >= lo[d] && pos_[i][d] <= lo[d] + length_[d]))
          throw std::logic_error("stepper: a sphere reached a wall its adapter declared unreached");
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) {
      Real& p = pos_[i][d];
      const Real len = length_[d];
      if (!box_.periodic[d] || (p >= lo[d] && p < lo[d] + len)) continue;
      const Real wraps = std::floor((p - lo[d]) / len);
      p -= len * wraps;
      // Sub-steps keep |wraps| <= 1 between rebuilds; counts wrap around modulo 2^32 (as
      // LAMMPS's image flags do modulo 1024) in runs long enough to pass that.
      std::uint32_t image = std::uint32_t(image_[slot_[i]][std::size_t(d)]) + std::uint32_t(std::int32_t(wraps));
      if (p >= lo[d] + len) p -= len, ++image;  // floor rounding at the top edge
      image_[slot_[i]][std::size_t(d)] = std::int32_t(image);
    }
  }
  if (big_.empty())
    grid_.sort(
        n, [this](std::size_t i) { return pos_[i]; }, cell_, cell_start_, order_);
  else
    grid_.sort(
        n, [this](std::size_t i) { return pos_[i]; }, [this](std::size_t i) { return big_[slot_[i]] != 0; }, cell_,
        cell_start_, order_);
  auto permute = [&](auto& a, auto& scratch) {
    scratch.resize(n);
    for (std::size_t k = 0; k < n; ++k) scratch[k] = a[order_[k]];
    a.swap(scratch);
  };
  // Positions also go to the rebuild reference and to coordinate arrays for the pair build,
  // in the same pass.
  scratch_v3_.resize(n), pos0_.resize(n);
  Real *const sx = pairs_.x(n), *const sy = pairs_.y(n), *const sz = pairs_.z(n);
  for (std::size_t k = 0; k < n; ++k) {
    const V3<Real> p = pos_[order_[k]];
    scratch_v3_[k] = p, pos0_[k] = p, sx[k] = p.x, sy[k] = p.y, sz[k] = p.z;
  }
  pos_.swap(scratch_v3_);
  permute(vel_, scratch_v3_);
  if (!kick_residual_.empty()) permute(kick_residual_, scratch_v3_);
  if (!omega_.empty()) permute(omega_, scratch_v3_);
  if constexpr (!Mono) {  // equal radii and masses need no reordering
    permute(r_, scratch_real_);
    permute(m_, scratch_real_);
  }
  permute(slot_, scratch_u32_);
  if (!pair_collisions_.empty()) permute(pair_collisions_, scratch_i64_);
  if (!sphere_virial_.empty()) {
    scratch_virial_.resize(6 * n);
    for (std::size_t k = 0; k < n; ++k)
      std::copy_n(&sphere_virial_[6 * std::size_t(order_[k])], 6, &scratch_virial_[6 * k]);
    sphere_virial_.swap(scratch_virial_);
  }
  if (observer_) observer_->reordered(order_.data(), n);
  resolver_.permute(order_);
  guard_.reset(n);
  index_kinematic();

  // Candidate list: every pair that could touch before the next rebuild.
  pairs_.build(pos_.data(), r_.data(), cell_start_.data(), n, big_.empty() ? std::uint32_t(n) : big_begin_);
  if (speeds_) {  // in the new order (a rebuild inside a step needs the current speeds)
    speed_.resize(n);
    for (std::size_t k = 0; k < n; ++k) speed_[k] = norm(vel_[k]);
  }
  bind_resolver();
  if (detect_auto_) sweep_ = sweep_wanted();
  ++counters_.rebuilds;
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::bind_resolver() {
  resolver_.bind({pos_.data(), vel_.data(), r_.data(), m_.data(), id_.data(), slot_.data(), pairs_.adj_start(),
                  pairs_.adj(), image_shift_, speeds_ ? speed_.data() : nullptr, pairs_.adj_plain_end(),
                  pair_collisions_.empty() ? nullptr : pair_collisions_.data(),
                  sphere_virial_.empty() ? nullptr : sphere_virial_.data(), observer_,
                  omega_.empty() ? nullptr : omega_.data(), kin_.empty() ? nullptr : kin_.data(), transport_});
}

template void Stepper<float, true>::rebuild();
template void Stepper<float, true>::bind_resolver();
template void Stepper<float, false>::rebuild();
template void Stepper<float, false>::bind_resolver();
template void Stepper<double, true>::rebuild();
template void Stepper<double, true>::bind_resolver();
template void Stepper<double, false>::rebuild();
template void Stepper<double, false>::bind_resolver();

}  // namespace hardsphere::detail
