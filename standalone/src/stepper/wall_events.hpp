#pragma once
//! The stepper's reflecting walls as events of the contact resolver: which walls a sphere's path
//! over its window ends beyond (straight lines, or parabolas under gravity) and the normal part
//! of a bounce, with the resting-contact rule under gravity. ContactResolver orders the bounces
//! with the pair contacts and adds the rest (tallies, the rough tangential impulse, re-predictions).
#include <algorithm>
#include <array>
#include <cmath>

#include "hardsphere/collision.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere {

template <class Real>
class WallEvents {
 public:
  //! Reflecting walls at lo[d] and hi[d] on every axis d that is not periodic.
  void set_walls(const std::array<bool, 3>& periodic, const std::array<Real, 3>& lo, const std::array<Real, 3>& hi) {
    n_wall_axes_ = 0;
    for (int d = 0; d < 3; ++d)
      if (!periodic[std::size_t(d)]) wall_axis_[n_wall_axes_++] = d;
    lo_ = lo;
    hi_ = hi;
  }
  //! A uniform acceleration (gravity) along the wall axes: flights are parabolas, so wall
  //! contacts are found on them. Pair contacts need nothing: relative motion stays straight.
  void set_gravity(const std::array<Real, 3>& g) {
    gravity_ = g;
    has_gravity_ = g[0] != Real(0) || g[1] != Real(0) || g[2] != Real(0);
  }
  //! Physics::resting_time (0: the sub-step).
  void set_resting_time(Real t) { resting_time_ = t; }
  bool any() const { return n_wall_axes_ > 0; }
  const std::array<Real, 3>& gravity() const { return gravity_; }

  //! Calls push(axis, back) for each wall the path of a sphere (radius r, at x moving at v now)
  //! over its window ends beyond, `back` the time before the end of the step it met it.
  template <class Push>
  void predict(const Vec3<Real>& x, const Vec3<Real>& v, Real r, Real window, Push&& push) const {
    for (int k = 0; k < n_wall_axes_; ++k) {
      const int d = wall_axis_[k];
      if (has_gravity_ && gravity_[std::size_t(d)] != Real(0)) {
        predict_in_flight(x[d], v[d], r, window, d, push);
        continue;
      }
      // The kernel's mirror on copies decides whether s went past a wall; it moves the
      // coordinate by twice the distance past the contact plane, which s covered since the bounce.
      Real xd = x[d], vd = v[d];
      if (kernel::reflect_from_walls(xd, vd, lo_[std::size_t(d)], hi_[std::size_t(d)], r) == Real(0)) continue;
      push(d, std::min(std::abs(xd - x[d]) / (Real(2) * std::abs(vd)), window));
    }
  }

  //! What a bounce did along its axis: the normal velocity at contact, the momentum per unit
  //! mass the wall took, and whether it was a resting contact.
  struct Bounce {
    Real v_before;
    double impulse;
    bool rested;
  };
  //! The normal part of a bounce off the wall of axis d, `back` before the end of a step of
  //! length dt: x and v (the sphere's coordinate and velocity along d at the end of the step)
  //! are mirrored at the contact, or left resting on the wall.
  Bounce reflect(Real& x, Real& v, int d, Real r, Real back, Real dt) const {
    const Real g = gravity_[std::size_t(d)];
    // The velocity at contact, whose reversal is the impulse the wall takes.
    const Real v_before = v - g * back;
    double impulse = 2.0 * std::abs(double(v_before));  // per unit mass
    bool rested = false;
    if (has_gravity_ && g != Real(0)) {
      const Real s = back;
      const Real x_contact = x - v * s + Real(0.5) * g * s * s;
      const Real lo = lo_[std::size_t(d)] + r, hi = hi_[std::size_t(d)] - r;
      const Real w = std::abs(x_contact - lo) <= std::abs(x_contact - hi) ? lo : hi;
      if (resting_contact(v_before, g, w == lo, dt)) {
        // Resting contact: bounces this slow would follow each other without end (a sphere at
        // rest on a floor bounces at once again). It leaves the wall at half the speed gravity
        // builds in the rest of the sub-step, so it is back on the wall exactly at its end: it
        // rests on the wall at every sub-step's end, the wall carries its weight, and its flight
        // stays the shared parabola of every other sphere.
        x = w;
        v = Real(0.5) * g * s;  // leaving at -g s / 2, arriving at +g s / 2
        impulse = std::abs(double(v_before)) + std::abs(double(v));
        rested = true;
      } else {
        kernel::reflect_in_flight(x, v, g, w, s);
      }
    } else {
      kernel::reflect_from_walls(x, v, lo_[std::size_t(d)], hi_[std::size_t(d)], r);
    }
    return {v_before, impulse, rested};
  }

 private:
  template <class Push>
  void predict_in_flight(Real x, Real v, Real r, Real window, int d, Push& push) const {
    const Real g = gravity_[std::size_t(d)];
    const Real lo = lo_[std::size_t(d)] + r, hi = hi_[std::size_t(d)] - r;
    // The earlier of the two walls it reached in its window (the larger back time).
    Real back =
        std::max(kernel::wall_back_time(x, v, g, lo, -1, window), kernel::wall_back_time(x, v, g, hi, +1, window));
    // Rounding can leave a sphere a hair beyond a wall at the start of its window (resting on a
    // floor, say), where no crossing is found: one that ends beyond it moving into it bounces
    // at the start of its window, as the straight-line mirror would have it.
    if (back < Real(0) && ((x < lo && v < Real(0)) || (x > hi && v > Real(0)))) back = window;
    if (back < Real(0)) return;
    push(d, back);
  }
  //! A wall contact at normal speed v_before (towards the wall) under the acceleration g along
  //! that axis is a resting contact when gravity pulls the sphere into that wall and it arrives
  //! no faster than gravity speeds it up in one sub-step (dt).
  bool resting_contact(Real v_before, Real g, bool lower_wall, Real dt) const {
    return (lower_wall ? g < Real(0) : g > Real(0)) &&
           std::abs(v_before) <= std::abs(g) * (resting_time_ > Real(0) ? resting_time_ : dt);
  }

  std::array<Real, 3> lo_{}, hi_{};       // wall positions
  std::array<Real, 3> gravity_{0, 0, 0};  // uniform acceleration (wall axes only)
  bool has_gravity_ = false;
  Real resting_time_ = 0;                           // see set_resting_time()
  int wall_axis_[3] = {0, 0, 0}, n_wall_axes_ = 0;  // the axes with walls
};

}  // namespace hardsphere
