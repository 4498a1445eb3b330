//! The fixed-step engine's StateExchange (spheres in, out and observed by slot, for adapters that
//! keep their own copy) and its state and samples for the caller.
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "stepper/stepper_engine.hpp"

namespace hardsphere::detail {

template <class Real, bool Mono>
void Stepper<Real, Mono>::copy_state(Vec3d* pos, Vec3d* vel) const {
  for (std::size_t k = 0; k < pos_.size(); ++k) {
    pos[k] = user_position(k);
    vel[k] = {double(vel_[k].x), double(vel_[k].y), double(vel_[k].z)};
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::scatter_state(const std::uint32_t* dest, const Vec3d* shift, double* x, double* v) const {
  const std::size_t n = pos_.size(), ahead = 16;  // rows are scattered: request them early
  for (std::size_t k = 0; k < n; ++k) {
    if (k + ahead < n && dest[k + ahead] != kNoRow) {
      __builtin_prefetch(x + 3 * std::size_t(dest[k + ahead]), 1);
      __builtin_prefetch(v + 3 * std::size_t(dest[k + ahead]), 1);
    }
    if (dest[k] == kNoRow) continue;
    double* xo = x + 3 * std::size_t(dest[k]);
    double* vo = v + 3 * std::size_t(dest[k]);
    const Vec3d p = user_position(k);
    xo[0] = p.x + shift[k].x, xo[1] = p.y + shift[k].y, xo[2] = p.z + shift[k].z;
    vo[0] = double(vel_[k].x), vo[1] = double(vel_[k].y), vo[2] = double(vel_[k].z);
  }
}

template <class Real, bool Mono>
double Stepper<Real, Mono>::mv2_sum() const {
  double sum = 0;
  for (std::size_t k = 0; k < vel_.size(); ++k) sum += double(m_[k]) * double(dot(vel_[k], vel_[k]));
  return sum;
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::set_velocities(const Vec3d* vel) {
  for (std::size_t k = 0; k < vel_.size(); ++k) vel_[k] = {Real(vel[k].x), Real(vel[k].y), Real(vel[k].z)};
  clear_kick_residual();
  refresh_speed_bound();
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::copy_velocities(const std::uint32_t* slots, std::size_t count, Vec3d* out) const {
  for (std::size_t i = 0; i < count; ++i) {
    const auto& u = vel_[slots[i]];
    out[i] = {double(u.x), double(u.y), double(u.z)};
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::set_spheres(const std::uint32_t* slots, std::size_t count, const Vec3d* pos,
                                      const Vec3d* vel) {
  // A changed position is a displacement like any other: the next drift measures it from the
  // rebuild position, so the list guard sees it. The speed bound stays an upper bound if
  // raised by the new speeds (the other spheres' are below it): no pass over every sphere.
  Real v2 = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t k = slots[i];
    pos_[k] = {Real(pos[i].x - origin_[0]), Real(pos[i].y - origin_[1]), Real(pos[i].z - origin_[2])};
    vel_[k] = {Real(vel[i].x), Real(vel[i].y), Real(vel[i].z)};
    if (!kick_residual_.empty()) kick_residual_[k] = {};
    v2 = std::max(v2, dot(vel_[k], vel_[k]));
  }
  resolver_.set_speed_bound(std::max(resolver_.speed_bound(), std::sqrt(v2) + path_bend()));
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::gather_velocities(const std::uint32_t* src, const double* v) {
  for (std::size_t k = 0; k < vel_.size(); ++k) {
    const double* vi = v + 3 * std::size_t(src[k]);
    vel_[k] = {Real(vi[0]), Real(vi[1]), Real(vi[2])};
  }
  clear_kick_residual();
  refresh_speed_bound();
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::scatter_omega(const std::uint32_t* dest, double* omega) const {
  if (omega_.empty()) {  // smooth: the spins carried
    for (std::size_t k = 0; k < slot_.size(); ++k)
      if (dest[k] != kNoRow) {
        const Vec3d w = spins_.at(slot_[k]);
        double* o = omega + 3 * std::size_t(dest[k]);
        o[0] = w.x, o[1] = w.y, o[2] = w.z;
      }
    return;
  }
  for (std::size_t k = 0; k < omega_.size(); ++k) {
    if (dest[k] == kNoRow) continue;
    double* o = omega + 3 * std::size_t(dest[k]);
    o[0] = double(omega_[k].x), o[1] = double(omega_[k].y), o[2] = double(omega_[k].z);
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::gather_omega(const std::uint32_t* src, const double* omega) {
  if (omega_.empty()) {
    for (std::size_t k = 0; k < slot_.size(); ++k) {
      const double* o = omega + 3 * std::size_t(src[k]);
      spins_.set(slot_[k], {o[0], o[1], o[2]}, slot_.size());
    }
    return;
  }
  for (std::size_t k = 0; k < omega_.size(); ++k) {
    const double* o = omega + 3 * std::size_t(src[k]);
    omega_[k] = {Real(o[0]), Real(o[1]), Real(o[2])};
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::copy_omega(const std::uint32_t* slots, std::size_t count, Vec3d* out) const {
  for (std::size_t i = 0; i < count; ++i) {
    if (omega_.empty()) {
      out[i] = spins_.at(slot_[slots[i]]);
      continue;
    }
    const auto& w = omega_[slots[i]];
    out[i] = {double(w.x), double(w.y), double(w.z)};
  }
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::set_omega(const std::uint32_t* slots, std::size_t count, const Vec3d* w) {
  if (omega_.empty()) {
    for (std::size_t i = 0; i < count; ++i) spins_.set(slot_[slots[i]], w[i], slot_.size());
    return;
  }
  for (std::size_t i = 0; i < count; ++i) omega_[slots[i]] = {Real(w[i].x), Real(w[i].y), Real(w[i].z)};
}

template <class Real, bool Mono>
double Stepper<Real, Mono>::iw2_sum() const {
  double sum = 0;
  for (std::size_t k = 0; k < omega_.size(); ++k)
    sum += inertia_ * double(m_[Mono ? 0 : k]) * double(r_[Mono ? 0 : k]) * double(r_[Mono ? 0 : k]) *
           double(dot(omega_[k], omega_[k]));
  return sum;
}

template <class Real, bool Mono>
ParticleSystem Stepper<Real, Mono>::state() const {
  const std::size_t n = pos_.size();
  std::vector<std::size_t> by_id(n);  // slots are id ranks
  for (std::size_t k = 0; k < n; ++k) by_id[slot_[k]] = k;
  ParticleSystem out;
  out.box = user_box_;
  out.reserve(n);
  for (std::size_t s = 0; s < n; ++s) {
    const std::size_t k = by_id[s];
    Vec3d p = user_position(k);
    for (int d = 0; d < 3; ++d)  // rounding back to the caller's coordinates must not leave a wall
      if (!user_box_.periodic[d])
        p[d] = std::clamp(p[d], user_box_.lo[d] + double(r_[k]), user_box_.hi[d] - double(r_[k]));
    std::array<std::int32_t, 3> image{};
    for (std::size_t d = 0; d < 3; ++d)
      image[d] = std::int32_t(
          std::clamp(std::int64_t(image0_[s][d]) + image_[s][d], std::int64_t(INT32_MIN), std::int64_t(INT32_MAX)));
    const Vec3d w =
        omega_.empty() ? spins_.at(s) : Vec3d{double(omega_[k].x), double(omega_[k].y), double(omega_[k].z)};
    out.push_back(id_[s], type_[s], double(r_[k]), double(m_[k]), p,
                  {double(vel_[k].x), double(vel_[k].y), double(vel_[k].z)}, image, w);
  }
  wrap_periodic(out);
  return out;
}

template <class Real, bool Mono>
SphereSample Stepper<Real, Mono>::sphere(std::size_t index) const {
  const std::size_t n = pos_.size();
  if (index >= n)
    throw InputError("sphere index " + std::to_string(index) + " is out of range (" + std::to_string(n) + " spheres)");
  // Rebuilds move spheres in the cell order; only then is the position searched for again.
  if (slot_[sampled_at_] != index)
    sampled_at_ = std::size_t(std::find(slot_.begin(), slot_.end(), std::uint32_t(index)) - slot_.begin());
  const std::size_t k = sampled_at_;
  SphereSample out;
  out.unwrapped = user_position(k);
  for (std::size_t d = 0; d < 3; ++d)
    if (user_box_.periodic[d])
      out.unwrapped[int(d)] += double(std::int64_t(image0_[index][d]) + image_[index][d]) * user_box_.length(int(d));
  out.velocity = {double(vel_[k].x), double(vel_[k].y), double(vel_[k].z)};
  out.pair_collisions = pair_collisions_.empty() ? -1 : pair_collisions_[k];
  return out;
}

template class Stepper<float, true>;
template class Stepper<float, false>;
template class Stepper<double, true>;
template class Stepper<double, false>;

}  // namespace hardsphere::detail
