#pragma once
//! The stepper's reflecting walls as events of the contact resolver: which walls a sphere's path
//! over its window ends beyond (straight lines, or parabolas under gravity) and the normal part
//! of a bounce as the stepper moves it: the contact's wall, and the end-of-step coordinate after
//! the wall law (kernel::collide_wall(), contact_law.hpp) decided at it. ContactResolver orders
//! the bounces with the pair contacts and adds the rest (the law's call, tallies, re-predictions).
#include <algorithm>
#include <array>
#include <cmath>

#include "hardsphere/collision.hpp"
#include "hardsphere/contact_law.hpp"
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

  //! The wall a bounce off axis d touches, `back` before the end of the step (x, v: the sphere's
  //! coordinate and velocity along d at the end of the step): its side (-1: lower, +1: upper) and
  //! the contact plane of the centre.
  struct Contact {
    int side;
    Real plane;
  };
  Contact contact(Real x, Real v, int d, Real r, Real back) const {
    const Real g = gravity_[std::size_t(d)];
    const Real lo = lo_[std::size_t(d)] + r, hi = hi_[std::size_t(d)] - r;
    if (has_gravity_ && g != Real(0)) {  // the wall nearer to where the parabola was at contact
      const Real s = back;
      const Real x_contact = x - v * s + Real(0.5) * g * s * s;
      const bool lower = std::abs(x_contact - lo) <= std::abs(x_contact - hi);
      return {lower ? -1 : 1, lower ? lo : hi};
    }
    return {v < Real(0) ? -1 : 1, v < Real(0) ? lo : hi};  // straight: the wall it moves into
  }
  //! The resting contacts' threshold (kernel::resting_contact()): Physics::resting_time, or the
  //! step dt if that is 0.
  Real resting_time(Real dt) const { return resting_time_ > Real(0) ? resting_time_ : dt; }

  //! Moves x and v (along d, at the end of the step) as the wall law decided at `wall`, `back`
  //! before the end of the step: mirrored at the contact (elastic), left at `out.leave` (restituted),
  //! or left resting on the wall having left it at `out.leave` (kernel::collide_wall() with hop =
  //! back: back on the wall at the step's end, so the wall carries its weight and its flight stays
  //! the shared parabola of every other sphere).
  void reflect(Real& x, Real& v, int d, Real r, Real back, Contact wall, const kernel::WallOutcome<Real>& out) const {
    const bool rested = out.rested;
    const Real leave = out.leave;
    if (out.restituted) return kernel::leave_wall(x, v, gravity_[std::size_t(d)], wall.plane, back, leave);
    const Real g = gravity_[std::size_t(d)];
    if (has_gravity_ && g != Real(0)) {
      if (rested) {
        x = wall.plane;
        v = -leave;  // leaving at -g s / 2, arriving at +g s / 2
      } else {
        kernel::reflect_in_flight(x, v, g, wall.plane, back);
      }
    } else {
      kernel::reflect_from_walls(x, v, lo_[std::size_t(d)], hi_[std::size_t(d)], r);
    }
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

  std::array<Real, 3> lo_{}, hi_{};       // wall positions
  std::array<Real, 3> gravity_{0, 0, 0};  // uniform acceleration (wall axes only)
  bool has_gravity_ = false;
  Real resting_time_ = 0;                           // see set_resting_time()
  int wall_axis_[3] = {0, 0, 0}, n_wall_axes_ = 0;  // the axes with walls
};

}  // namespace hardsphere
