#pragma once
//! The spheres' motion in the event-driven engine. Positions are "delayed": each sphere stores
//! its position at its own last update time and is advanced only when it takes part in an event
//! or is observed. Between events a sphere flies straight, or on a parabola under uniform
//! acceleration along wall axes (relative motion then stays straight).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/always_inline.hpp"
#include "event/geometry.hpp"
#include "event/renumbering.hpp"
#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"

namespace hardsphere::event {

//! Everything a pair prediction reads about a sphere, in one cache line.
struct alignas(64) Body {
  double x, y, z;  // position at time t
  double t;        // time of the last update (delayed state)
  double vx, vy, vz;
  double r;  // radius
};

class Trajectories {
 public:
  Trajectories() = default;
  //! Sphere k is sphere orig[k] of sys at time 0, at position pos[orig[k]] (wrapped into the box).
  Trajectories(const ParticleSystem& sys, const std::vector<Vec3d>& pos, std::vector<std::uint32_t> orig,
               const Physics& physics);

  std::size_t size() const { return body_.size(); }
  const Body& operator[](std::size_t i) const { return body_[i]; }
  double mass(std::size_t i) const { return mass_[i]; }
  std::uint32_t input_index(std::size_t i) const { return orig_[i]; }
  bool has_gravity() const { return has_g_; }
  const std::array<double, 3>& gravity() const { return g_; }
  //! A new acceleration: only between events, with every sphere synced (rebase()).
  void set_gravity(const std::array<double, 3>& g) {
    g_ = g;
    has_g_ = g != std::array<double, 3>{0, 0, 0};
  }
  HS_ALWAYS_INLINE void prefetch(std::size_t i) const { __builtin_prefetch(&body_[i]); }

  //! Sphere i, for the event handling that brings it to a time (sync) or changes its course.
  Body& body(std::size_t i) { return body_[i]; }
  static void set_velocity(Body& s, const Vec3d& v) { s.vx = v.x, s.vy = v.y, s.vz = v.z; }
  //! Moves a and b (synced, at contact separation dr = a - b, minimum image) apart along dr, each
  //! by half, until they are a few roundings beyond contact sigma: for a pair whose approach is
  //! below the rounding of their velocities, which no impulse can resolve.
  static void part(Body& a, Body& b, const Vec3d& dr, double sigma) {
    const double len = std::sqrt(dr.x * dr.x + dr.y * dr.y + dr.z * dr.z);
    const double half = 0.5 * (sigma * (1 + 8 * std::numeric_limits<double>::epsilon()) - len) / len;
    if (!(half > 0)) return;
    a.x += half * dr.x, a.y += half * dr.y, a.z += half * dr.z;
    b.x -= half * dr.x, b.y -= half * dr.y, b.z -= half * dr.z;
  }
  //! Brings s, one of these spheres, to time `now`.
  void sync(Body& s, double now) const {
    const double dt = now - s.t;
    if (has_g_) {
      s.x += (s.vx + 0.5 * g_[0] * dt) * dt, s.vx += g_[0] * dt;
      s.y += (s.vy + 0.5 * g_[1] * dt) * dt, s.vy += g_[1] * dt;
      s.z += (s.vz + 0.5 * g_[2] * dt) * dt, s.vz += g_[2] * dt;
    } else {
      s.x += s.vx * dt;
      s.y += s.vy * dt;
      s.z += s.vz * dt;
    }
    s.t = now;
  }
  //! Sets the velocity of s (synced, touching a wall of axis d) along d to `leave`, on the contact
  //! plane exactly; returns the speed along d it had.
  double rest(Body& s, std::size_t d, double leave, const EventGeometry& geo) const {
    double* vel = d == 0 ? &s.vx : (d == 1 ? &s.vy : &s.vz);
    double* x = d == 0 ? &s.x : (d == 1 ? &s.y : &s.z);
    const double speed = std::abs(*vel), hi = geo.lo(d) + geo.len(d);
    *vel = leave;
    *x = leave > 0 ? geo.lo(d) + s.r : hi - s.r;
    return speed;
  }
  //! Reverses the velocity of s (synced, touching a wall of axis d); returns the speed along d
  //! it had.
  double reflect(Body& s, std::size_t d, const EventGeometry& geo) const {
    double* vel = d == 0 ? &s.vx : (d == 1 ? &s.vy : &s.vz);
    const double speed = std::abs(*vel);
    *vel = -*vel;
    if (has_g_) {  // on the contact plane exactly: rounding must not leave it beyond the wall
      double* x = d == 0 ? &s.x : (d == 1 ? &s.y : &s.z);
      const double hi = geo.lo(d) + geo.len(d);
      *x = std::clamp(*x, geo.lo(d) + s.r, hi - s.r);
    }
    return speed;
  }
  //! Wraps the periodic coordinates of sphere i (synced) into the box, counting the box lengths
  //! removed; true if any was.
  bool wrap_into_box(std::size_t i, const EventGeometry& geo) {
    Body& s = body_[i];
    double* pos[3] = {&s.x, &s.y, &s.z};
    bool wrapped = false;
    for (std::size_t d = 0; d < 3; ++d) {
      if (!geo.periodic(d)) continue;
      if (*pos[d] < geo.lo(d))
        *pos[d] += geo.len(d), wrapped = true, --wraps_[orig_[i]][d];
      else if (*pos[d] >= geo.lo(d) + geo.len(d))
        *pos[d] -= geo.len(d), wrapped = true, ++wraps_[orig_[i]][d];
    }
    return wrapped;
  }

  //! Every sphere brought to `now`, which becomes time 0 of every sphere.
  void rebase(double now);
  void permute(const Renumbering& r) {
    r.permute(body_);
    r.permute(mass_);
    r.permute(orig_);
  }

  //! Fills the positions, velocities and images of `out` (the spheres by input index, with their
  //! input images) with the state at `now`.
  void observe(double now, ParticleSystem& out) const;
  //! Input sphere `index` at `now`, without advancing the others; `proto` holds the input images.
  SphereSample sample(std::size_t index, double now, const ParticleSystem& proto) const;

 private:
  void state_at(const Body& s, double dt, Vec3d& pos, Vec3d& vel) const;

  std::vector<Body> body_;
  std::vector<double> mass_;
  std::vector<std::uint32_t> orig_;                 // internal index -> input index
  std::vector<std::array<std::int64_t, 3>> wraps_;  // input index: box lengths removed by wrapping
  std::array<double, 3> g_{0, 0, 0};
  bool has_g_ = false;
  mutable std::size_t sampled_at_ = 0;  // sample()'s last internal index: valid until a renumbering
};

}  // namespace hardsphere::event
