#pragma once
//! The stepper's shaped walls (wall_shapes.hpp) as events of the contact resolver, detected a
//! posteriori as the box faces are: a sphere whose path over its window ends overlapping a wall
//! goes back to its contact time, found analytically where the shape allows (a plane; a sphere
//! or a cylinder on a straight path, a cylinder under gravity along its axis) and otherwise by
//! bisection to rounding; outside a convex obstacle (a cylinder's or a sphere's outside) a path
//! that touches and leaves it within its window is caught at its closest approach. A wall whose
//! geometry moves (translate, wiggle) is followed in its own frame: a translation keeps the path
//! relative to it a parabola (the same roots), a wiggled plane's gap is advanced conservatively
//! with a bound on its second derivative (wiggle_back). The geometry is in double whatever the
//! engine's Real.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "hardsphere/collision.hpp"
#include "hardsphere/contact_law.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/physics.hpp"
#include "hardsphere/vec3.hpp"
#include "hardsphere/wall_shapes.hpp"

namespace hardsphere {

template <class Real>
class ShapeEvents {
 public:
  //! The walls, moved into the engine's coordinates (origin: the box's lower corner, which the
  //! engine subtracts), their kernel laws (the spheres' tangential law where a wall gives none)
  //! and the rounding its positions carry over `extent` (the largest box length).
  void set_shapes(const Physics& p, const std::array<double, 3>& origin, double extent) {
    shapes_.clear();
    laws_.clear();
    const Vec3<double> o{origin[0], origin[1], origin[2]};
    double size = extent;
    for (WallShape w : p.shapes) {
      w.point -= o;
      if (w.kind == ShapeKind::Cylinder || w.kind == ShapeKind::Cone) {
        w.lo -= origin[std::size_t(w.axis)];
        w.hi -= origin[std::size_t(w.axis)];
      }
      size = std::max({size, norm(w.point) + w.radius, w.radius_lo, w.radius_hi});
      w.time = w.start_time();  // the wall's time at this engine's clock 0
      w.clock = nullptr;
      shapes_.push_back(w);
      const double beta = w.law.tangential_restitution.value_or(p.tangential_restitution);
      const double mu = w.law.friction.value_or(p.friction);
      laws_.push_back({w.law.restitution, {beta, mu, p.inertia}});
    }
    totals_.assign(shapes_.size(), WallShapeTotals{});
    // A gap within a few roundings of the positions is a touch: a sphere left on the surface by a
    // bounce or a rest is not taken for one overlapping it.
    tol_ = 16 * double(std::numeric_limits<Real>::epsilon()) * size;
  }
  //! The engine's gravity, as its drift applies it (set again when it changes between steps).
  void set_gravity(const std::array<Real, 3>& g) {
    g_ = {double(g[0]), double(g[1]), double(g[2])};
    g_norm_ = norm(g_);
  }
  //! Wall k's surface turns at omega from now on (the geometry stays: only the surface moves).
  void set_rotation(std::size_t k, double omega) {
    if (!std::isfinite(omega))
      throw InputError(shapes_.at(k).source + ": rotation rate " + std::to_string(omega) + " must be finite");
    shapes_.at(k).omega = omega;
  }
  //! The end of the current step on the engine's clock (its time since it was made).
  void set_step_end(double t) { end_ = t; }
  bool any() const { return !shapes_.empty(); }
  std::size_t size() const { return shapes_.size(); }
  const kernel::WallLaw<double>& law(std::size_t k) const { return laws_[k]; }
  const Vec3<double>& gravity() const { return g_; }
  bool moving(std::size_t k) const { return shapes_[k].moving(); }
  std::vector<WallShapeTotals>& totals() { return totals_; }
  const std::vector<WallShapeTotals>& totals() const { return totals_; }

  //! Calls push(k, back) for each wall k the path of a sphere (radius r, at x moving at v at the
  //! end of its window) met in its window, `back` the time before the end of the step it did.
  template <class Push>
  void predict(const Vec3<Real>& x, const Vec3<Real>& v, Real r, Real window, Push&& push) const {
    const Vec3<double> xe{double(x.x), double(x.y), double(x.z)}, ve{double(v.x), double(v.y), double(v.z)};
    const double w = double(window), a = double(r);
    // How far the sphere can have come in its window: a wall farther than that costs one gap.
    const double reach = norm(ve) * w + g_norm_ * w * w + tol_;
    for (std::size_t k = 0; k < shapes_.size(); ++k) {
      const WallShape& s = shapes_[k];
      if (s.geometry_moves()) {
        const double back = moving_back_time(s, xe, ve, a, w, reach);
        if (back >= 0) push(k, Real(back));
        continue;
      }
      const double fe = shape_gap(s, xe, a);
      if (fe > reach) continue;
      const double back = back_time(s, xe, ve, a, w, fe);
      if (back >= 0) push(k, Real(back));
    }
  }

  //! The contact's unit normal (from the wall to the sphere), the surface's velocity there and,
  //! for a wall whose geometry moves, the sphere's position relative to it (x otherwise).
  struct Contact {
    Vec3<double> n, u, x;
  };
  //! A sphere of radius a at x meeting wall k `back` before the end of the step.
  Contact contact(std::size_t k, Vec3<double> x, double a, double back) const {
    const WallShape& s = shapes_[k];
    if (s.geometry_moves()) {
      const double t = s.time + end_ - back;
      x -= shape_displacement(s, t);
      const Vec3<double> n = shape_normal(s, x);
      return {n, shape_surface_velocity(s, x - a * n) + shape_motion_velocity(s, t), x};
    }
    const Vec3<double> n = shape_normal(s, x);
    return {n, shape_surface_velocity(s, x - a * n), x};
  }

  //! What a contact did: whether it changed the sphere, rested, the energy it took and the work
  //! the wall did (the spheres' energy gained plus what the contact took; walls at rest: none).
  struct Outcome {
    //! placed: the law did nothing (a path sliding along a concave wall, receding at the start),
    //! the sphere only put back on the surface at the step's end: no contact to count.
    bool changed = false, rested = false, placed = false;
    double dissipated_normal = 0, dissipated_tangential = 0, work = 0;
  };
  //! Sphere (x, v, w at the end of the step; radius a, mass m) met wall k `back` before the end:
  //! back along its path (a parabola under gravity) to the contact, the wall law there
  //! (kernel::collide_surface() with the surface's velocity), on along the new path; in double.
  template <bool Rough, class Recent>
  Outcome collide(std::size_t k, Vec3<Real>& x, Vec3<Real>& v, Vec3<Real>* omega, Real a_in, Real m_in, Real back,
                  Real resting_time, Recent&& recent) {
    const double t = double(back), a = double(a_in), m = double(m_in);
    const Vec3<double> xe{double(x.x), double(x.y), double(x.z)}, ve{double(v.x), double(v.y), double(v.z)};
    Vec3<double> xc = xe - t * ve + (0.5 * t * t) * g_;
    const Vec3<double> vc = ve - t * g_;
    const Contact wall = contact(k, xc, a, t);
    Outcome r;
    // A contact at the window's start may be inside the wall (a resting hop along a curved wall
    // ends ~v_t^2 dt^2 / 2R inside it; rounding): the sphere goes back onto the surface along
    // the normal, and the potential energy that takes counts as the wall's work.
    const double gap = shape_gap(shapes_[k], wall.x, a);
    Vec3<double> w{}, w0{};
    if constexpr (Rough) w = w0 = {double(omega->x), double(omega->y), double(omega->z)};
    // Where gravity pulls a sphere onto a wiggled wall it rests under gravity relative to the
    // wall (its acceleration taken off): it rides a plate accelerating down slower than g and
    // leaves one that is faster (the bouncing ball); without that pull there is no rest.
    const WallShape& s = shapes_[k];
    const bool relative = s.wiggle_axis >= 0 && dot(g_, wall.n) < 0;
    const Vec3<double> g_law = relative ? g_ - shape_motion_acceleration(s, s.time + end_ - t) : g_;
    const auto out = kernel::collide_surface<Rough>(laws_[k], wall.n, wall.u, vc, g_law, double(resting_time), t,
                                                    Rough ? &w : nullptr, m, a, recent);
    if (!out.wall.contact.changed) {
      // Sliding along a concave wall (the limit of ever shorter chords) ends inside it by
      // ~v_t^2 t^2 / 2R: it ends on the surface.
      Vec3<double> xend = xe;
      if (!put_on_surface(s, xend, a, m, r.work)) return r;
      x = {Real(xend.x), Real(xend.y), Real(xend.z)};
      r.changed = r.placed = true;
      totals_[k].work += r.work;
      return r;
    }
    if (gap < 0) {
      xc -= gap * wall.n;
      r.work += m * gap * dot(g_, wall.n);
    }
    const Vec3<double> v1 = vc + out.dv;
    Vec3<double> x1 = xc + t * v1 + (0.5 * t * t) * g_;
    const Vec3<double> v_end = v1 + t * g_;
    // A resting hop along a concave wall (a drum, a bowl) ends ~v_t^2 t^2 / 2R inside it: it ends
    // on the surface instead, so no state a step leaves overlaps a wall (which a stepper made from
    // it refuses), the potential energy that takes again the wall's work.
    if (out.wall.rested) put_on_surface(s, x1, a, m, r.work);
    x = {Real(x1.x), Real(x1.y), Real(x1.z)};
    v = {Real(v_end.x), Real(v_end.y), Real(v_end.z)};
    r.changed = true, r.rested = out.wall.rested;
    r.dissipated_normal = out.wall.contact.dissipated_normal;
    r.dissipated_tangential = out.wall.contact.dissipated_tangential;
    if (shapes_[k].moving()) {  // a wall at rest does none: its sum would be rounding
      r.work += 0.5 * m * (dot(v1, v1) - dot(vc, vc)) + r.dissipated_normal + r.dissipated_tangential;
      if constexpr (Rough) r.work += 0.5 * laws_[k].roughness.q * m * a * a * (dot(w, w) - dot(w0, w0));
    }
    if constexpr (Rough) *omega = {Real(w.x), Real(w.y), Real(w.z)};
    WallShapeTotals& total = totals_[k];
    total.work += r.work;
    ++(r.rested ? total.resting_contacts : total.collisions);
    return r;
  }

 private:
  //! Moves a sphere at x (radius a, mass m) at the end of the step that overlaps wall s back onto
  //! its surface along the normal, adding the work that takes against gravity to `work`; false:
  //! it was clear.
  bool put_on_surface(const WallShape& s, Vec3<double>& x, double a, double m, double& work) const {
    const Vec3<double> shift = s.geometry_moves() ? shape_displacement(s, s.time + end_) : Vec3<double>{};
    const Vec3<double> xr = x - shift;
    const double gap = shape_gap(s, xr, a);
    if (!(gap < 0)) return false;
    const Vec3<double> n = shape_normal(s, xr);
    x -= gap * n;
    work += m * gap * dot(g_, n);
    return true;
  }
  Vec3<double> at(Vec3<double> xe, Vec3<double> v, double t) const { return xe - t * v + (0.5 * t * t) * g_; }

  //! back_time() for a wall whose geometry moves, or -1; `reach` as predict()'s.
  double moving_back_time(const WallShape& s, Vec3<double> xe, Vec3<double> v, double a, double w, double reach) const {
    const double te = s.time + end_;  // the wall's time at the window's end
    const Vec3<double> xr = xe - shape_displacement(s, te);
    const bool wiggle_moves_gap = s.wiggle_axis >= 0 && s.kind == ShapeKind::Plane && s.normal[s.wiggle_axis] != 0;
    if (!wiggle_moves_gap) {
      // In the frame of the translation (a wiggle along a cylinder's axis or in a plane's
      // surface changes no gap) the path is the same parabola, relative velocity v - V.
      const Vec3<double> vr = v - s.translate;
      const double fe = shape_gap(s, xr, a);
      if (fe > reach + norm(s.translate) * w) return -1;
      return back_time(s, xr, vr, a, w, fe);
    }
    const double fe = shape_gap(s, xr, a);
    const double omega = 2 * M_PI / s.period;
    if (fe > reach + (norm(s.translate) + s.amplitude * omega) * w) return -1;
    return wiggle_back(s, xe, v, a, w, te);
  }

  //! A wiggled plane: the gap along the sphere's parabola less the wall's motion,
  //! f(b) = n.(x(b) - p - D(te - b)) - a at back time b, whose second derivative is bounded by
  //! M = |n.g| + A omega^2 |n_axis|. From the window's start f is advanced conservatively (the
  //! first b at which the bound f + f' s - M s^2 / 2 could reach -tol), so no graze is missed; the
  //! contact is where the sphere is within tol of the plane and approaching it.
  double wiggle_back(const WallShape& s, Vec3<double> xe, Vec3<double> v, double a, double w, double te) const {
    const Vec3<double> n = s.normal;
    const double omega = 2 * M_PI / s.period;
    const double M = std::abs(dot(g_, n)) + s.amplitude * omega * omega * std::abs(n[s.wiggle_axis]);
    const auto gap = [&](double b) { return dot(at(xe, v, b) - s.point - shape_displacement(s, te - b), n) - a; };
    // Its rate forward in time: the normal velocity relative to the wall.
    const auto rate = [&](double b) { return dot(v - b * g_ - shape_motion_velocity(s, te - b), n); };
    double b = w, f = gap(b), d = rate(b), before = w;
    if (f < -tol_) {
      if (d < 0) return w;  // overlapping at the start and moving in: it bounces there
      f = 0;                // moving out: it has just left the wall (as back_time())
    }
    for (int it = 0; it < 200; ++it) {
      if (f < -tol_) {  // past the surface (the bound is exact only to rounding): bisect back
        double lo = b, hi = before;
        for (int k = 0; k < 200; ++k) {
          const double mid = 0.5 * (lo + hi);
          if (!(mid > lo && mid < hi)) break;
          (gap(mid) < 0 ? lo : hi) = mid;
        }
        return hi;
      }
      if (f <= tol_ && d < 0) return b;
      const double c = std::max(f, 0.0) + tol_;
      const double step = M > 0 ? (d + std::sqrt(d * d + 2 * M * c)) / M : (d < 0 ? c / -d : w);
      if (!(step < b)) return -1;  // f stays above -tol to the window's end
      before = b;
      b -= step;
      f = gap(b);
      d = rate(b);
    }
    return gap(0) < -tol_ ? b : -1;  // a long graze: the overlap at the end is resolved at the last bound
  }

  //! The back time of the contact in [0, w], or -1: fe is the gap at the window's end.
  double back_time(const WallShape& s, Vec3<double> xe, Vec3<double> v, double a, double w, double fe) const {
    const double fs = shape_gap(s, at(xe, v, w), a);
    if (fe < -tol_) {
      // Touching or overlapping at the window's start and moving in then: it bounces there (a
      // sphere resting on a curved wall ends its hop a little inside it; bounce_shape() puts it
      // back on the surface). Moving out there, it has just left the wall: no contact.
      if (!(fs > 0)) {
        const Vec3<double> x0 = at(xe, v, w);
        if (dot(v - w * g_, shape_normal(s, x0)) < 0) return w;
        // Leaving the surface and inside it at the end: a chord (a hop along a concave wall, or
        // a plane's under gravity) meets the wall again where its gap closes; a path never clear
        // of it slides along it: a contact at the start, which puts its end on the surface.
        const double tp = golden(s, xe, v, a, w, 1);
        return shape_gap(s, at(xe, v, tp), a) > tol_ ? root(s, xe, v, a, 0, tp) : w;
      }
      return root(s, xe, v, a, 0, w);
    }
    if (!s.convex_obstacle() || !(fs > -tol_)) return -1;
    const double tm = closest(s, xe, v, a, w);  // a graze within the window?
    if (!(shape_gap(s, at(xe, v, tm), a) < -tol_)) return -1;
    return root(s, xe, v, a, tm, w);
  }

  //! Whether the wall's gap along a path is a quadratic's: no gravity, a plane, or a cylinder
  //! whose axis gravity is along (the path across the axis is then a straight line).
  bool straight(const WallShape& s) const {
    if (g_norm_ == 0) return true;
    if (s.kind == ShapeKind::Plane) return true;  // the normal coordinate is a parabola: a quadratic
    if (s.kind == ShapeKind::Cylinder) {
      Vec3<double> across = g_;
      across[s.axis] = 0;
      return dot(across, across) == 0;
    }
    return false;
  }

  //! The contact time between `lo` (overlapping) and `hi` (clear), larger times earlier: the
  //! quadratic's root where the shape allows, else bisection to rounding; the clear side.
  double root(const WallShape& s, Vec3<double> xe, Vec3<double> v, double a, double lo, double hi) const {
    if (straight(s) && s.kind != ShapeKind::Cone) {
      const double t = analytic(s, xe, v, a, hi);
      if (t >= lo && t <= hi && !(shape_gap(s, at(xe, v, t), a) < -tol_)) return t;
    }
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (!(mid > lo && mid < hi)) break;
      if (shape_gap(s, at(xe, v, mid), a) < 0)
        lo = mid;
      else
        hi = mid;
    }
    return hi;
  }

  //! The quadratic's root: a plane's normal coordinate on its parabola (kernel::wall_back_time),
  //! a sphere's or cylinder's squared distance on a straight line (inside: where it left the
  //! allowed ball, the smaller root; outside: where it entered the obstacle, the larger).
  double analytic(const WallShape& s, Vec3<double> xe, Vec3<double> v, double a, double window) const {
    if (s.kind == ShapeKind::Plane)
      return kernel::wall_back_time(dot(xe - s.point, s.normal), dot(v, s.normal), dot(g_, s.normal), a, -1, window);
    Vec3<double> p = xe - s.point, u = v;
    if (s.kind == ShapeKind::Cylinder) p[s.axis] = 0, u[s.axis] = 0;
    const double reach = s.inside ? s.radius - a : s.radius + a;
    const double A = dot(u, u), b = dot(p, u), c = dot(p, p) - reach * reach;
    const double disc = b * b - A * c;
    if (!(A > 0) || !(disc >= 0)) return -1;
    const double q = b + std::copysign(std::sqrt(disc), b);  // cancellation-free pair
    if (q == 0) return -1;
    const double r1 = q / A, r2 = c / q;
    return s.inside ? std::min(r1, r2) : std::max(r1, r2);
  }

  //! The time of the path's closest approach to a convex obstacle in [0, w]: the straight line's,
  //! or a golden-section search on the parabola.
  double closest(const WallShape& s, Vec3<double> xe, Vec3<double> v, double a, double w) const {
    if (straight(s)) {
      Vec3<double> p = xe - s.point, u = v;
      if (s.kind == ShapeKind::Cylinder) p[s.axis] = 0, u[s.axis] = 0;
      const double A = dot(u, u);
      return A > 0 ? std::clamp(dot(p, u) / A, 0.0, w) : 0.0;
    }
    return golden(s, xe, v, a, w, -1);
  }

  //! The time in [0, w] of the path's largest gap (sign 1) or smallest (-1), by golden section:
  //! the gap along a path near a convex obstacle falls once and rises, along one leaving a
  //! concave wall or a plane rises once and falls.
  double golden(const WallShape& s, Vec3<double> xe, Vec3<double> v, double a, double w, double sign) const {
    const double phi = 0.5 * (std::sqrt(5.0) - 1);
    double lo = 0, hi = w;
    double t1 = hi - phi * (hi - lo), t2 = lo + phi * (hi - lo);
    double f1 = sign * shape_gap(s, at(xe, v, t1), a), f2 = sign * shape_gap(s, at(xe, v, t2), a);
    for (int it = 0; it < 60 && hi - lo > 1e-15 * w; ++it) {
      if (f1 > f2) {
        hi = t2, t2 = t1, f2 = f1;
        t1 = hi - phi * (hi - lo);
        f1 = sign * shape_gap(s, at(xe, v, t1), a);
      } else {
        lo = t1, t1 = t2, f1 = f2;
        t2 = lo + phi * (hi - lo);
        f2 = sign * shape_gap(s, at(xe, v, t2), a);
      }
    }
    return f1 > f2 ? t1 : t2;
  }

  std::vector<WallShape> shapes_;
  std::vector<kernel::WallLaw<double>> laws_;
  std::vector<WallShapeTotals> totals_;
  Vec3<double> g_{};
  double g_norm_ = 0, tol_ = 0, end_ = 0;
};

}  // namespace hardsphere
