//! The fixed-step engine's StateExchange (spheres in, out and observed by slot, for adapters that
//! keep their own copy) and its state and samples for the caller.
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "stepper/stepper_engine.hpp"

namespace hardsphere::detail {

// The field list: one accessor per SphereField, each field's value in slot k as doubles.
template <class Real, bool Mono>
struct Stepper<Real, Mono>::PositionField {
  static Vec3d get(const Stepper& s, std::size_t k) { return s.user_position(k); }
  static void put(Stepper& s, std::size_t k, const Vec3d& p) {
    s.pos_[k] = {Real(p.x - s.origin_[0]), Real(p.y - s.origin_[1]), Real(p.z - s.origin_[2])};
  }
};

template <class Real, bool Mono>
struct Stepper<Real, Mono>::VelocityField {
  static Vec3d get(const Stepper& s, std::size_t k) {
    return {double(s.vel_[k].x), double(s.vel_[k].y), double(s.vel_[k].z)};
  }
  static void put(Stepper& s, std::size_t k, const Vec3d& v) {
    s.vel_[k] = {Real(v.x), Real(v.y), Real(v.z)};
    if (!s.kick_residual_.empty()) s.kick_residual_[k] = {};  // earlier kicks' rounding is not theirs
  }
};

template <class Real, bool Mono>
struct Stepper<Real, Mono>::OmegaField {  // smooth scenes: the spins carried, by id rank
  static Vec3d get(const Stepper& s, std::size_t k) {
    if (s.omega_.empty()) return s.spins_.at(s.slot_[k]);
    return {double(s.omega_[k].x), double(s.omega_[k].y), double(s.omega_[k].z)};
  }
  static void put(Stepper& s, std::size_t k, const Vec3d& w) {
    if (s.omega_.empty())
      s.spins_.set(s.slot_[k], w, s.slot_.size());
    else
      s.omega_[k] = {Real(w.x), Real(w.y), Real(w.z)};
  }
};

template <class Real, bool Mono>
template <class Fn>
void Stepper<Real, Mono>::with_field(SphereField field, Fn&& fn) {
  switch (field) {
    case SphereField::Position:
      return fn(PositionField{});
    case SphereField::Velocity:
      return fn(VelocityField{});
    case SphereField::Omega:
      return fn(OmegaField{});
  }
  throw std::invalid_argument("StateExchange: unknown SphereField " + std::to_string(int(field)));
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::copy(SphereField field, const std::uint32_t* slots, std::size_t count, Vec3d* out) const {
  with_field(field, [&](auto f) {
    for (std::size_t i = 0; i < count; ++i) out[i] = f.get(*this, slots ? slots[i] : i);
  });
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::set(SphereField field, const std::uint32_t* slots, std::size_t count, const Vec3d* in) {
  with_field(field, [&](auto f) {
    for (std::size_t i = 0; i < count; ++i) f.put(*this, slots ? slots[i] : i, in[i]);
  });
  field_written(field, slots, count);
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::scatter(SphereField field, const std::uint32_t* dest, double* out) const {
  with_field(field, [&](auto f) {
    for (std::size_t k = 0; k < slot_.size(); ++k) {
      if (dest[k] == kNoRow) continue;
      const Vec3d w = f.get(*this, k);
      double* o = out + 3 * std::size_t(dest[k]);
      o[0] = w.x, o[1] = w.y, o[2] = w.z;
    }
  });
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::gather(SphereField field, const std::uint32_t* src, const double* in) {
  with_field(field, [&](auto f) {
    for (std::size_t k = 0; k < slot_.size(); ++k) {
      const double* r = in + 3 * std::size_t(src[k]);
      f.put(*this, k, {r[0], r[1], r[2]});
    }
  });
  field_written(field, nullptr, slot_.size());
}

template <class Real, bool Mono>
void Stepper<Real, Mono>::field_written(SphereField field, const std::uint32_t* slots, std::size_t count) {
  if (field != SphereField::Velocity) return;
  for (const std::uint32_t k : kin_at_) kin_vel_[slot_[k]] = vel_[k];  // a kinematic sphere moves on as set
  if (!slots && count == vel_.size()) {
    refresh_speed_bound();
    return;
  }
  // The other spheres' speeds are below the bound, so raising it by the new ones keeps it an
  // upper bound without a pass over every sphere.
  Real v2 = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t k = slots ? slots[i] : i;
    v2 = std::max(v2, dot(vel_[k], vel_[k]));
  }
  resolver_.set_speed_bound(std::max(resolver_.speed_bound(), std::sqrt(v2) + path_bend()));
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
  if (!kin_rank_.empty()) out.kinematic = kin_rank_;
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
