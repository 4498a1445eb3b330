#pragma once
//! Walls other than the box faces: planes of any orientation, cylinders, spheres and cones (a
//! hopper), each with its own law and, for a drum or a shear cell, a moving surface. The geometry
//! here (gap, contact normal, the surface's velocity) is the one the stepper detects and collides
//! with and the one validation checks the initial state against, in double.
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "hardsphere/vec3.hpp"

namespace hardsphere {

//! The law of one wall (the wall an infinite mass): normal restitution and, for rough spheres,
//! Walton's tangential law, as the pair law has them. Unset tangential parameters take the
//! spheres' (Physics::tangential_restitution, friction), which is what walls did before they had
//! laws of their own.
struct WallLaw {
  double restitution = 1.0;                      //!< e_w in (0, 1]; 1: elastic
  std::optional<double> tangential_restitution;  //!< beta_w in [-1, 1]; rough spheres only
  std::optional<double> friction;                //!< mu_w >= 0 (infinity: no sliding); rough spheres only
  bool operator==(const WallLaw& o) const {
    return restitution == o.restitution && tangential_restitution == o.tangential_restitution && friction == o.friction;
  }
  bool operator!=(const WallLaw& o) const { return !(*this == o); }
};

enum class ShapeKind { Plane, Cylinder, Sphere, Cone };

//! One shaped wall. A rotating or shearing wall moves only its surface (a drum turns in place),
//! which the contact law sees as the wall's velocity; `translate` and `wiggle` move its geometry
//! rigidly (a piston, a vibrated plate): the fields below give it at its time 0, and
//! shape_displacement() how far it has gone at a time.
struct WallShape {
  ShapeKind kind = ShapeKind::Plane;
  //! Plane: a point on it. Cylinder, cone: a point on the axis (the axial coordinate unused).
  //! Sphere: the centre.
  Vec3<double> point{};
  Vec3<double> normal{0, 0, 1};  //!< plane: towards the spheres' side (validation makes it unit)
  int axis = 2;                  //!< cylinder, cone: the axis (0 x, 1 y, 2 z); sphere: the rotation's
  double radius = 0;             //!< cylinder, sphere
  bool inside = true;            //!< cylinder, sphere: the spheres are inside (a cone: always)
  //! Cylinder: the axial extent of an open tube (infinite: unbounded); cone: where its radii are
  //! given (both finite, lo < hi), its open ends.
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  double radius_lo = 0, radius_hi = 0;  //!< cone: radii at lo and hi
  //! Angular velocity of the surface: cylinder, sphere, cone about +axis through `point`; plane
  //! about its normal through `point` (a turning plate: a drum's end walls).
  double omega = 0;
  Vec3<double> surface_velocity{};  //!< plane: the surface's velocity in its plane (shear)
  Vec3<double> translate{};         //!< the geometry's constant velocity (any shape)
  //! The geometry oscillating along axis `wiggle_axis` (-1: none) as fix wall/gran's wiggle:
  //! displacement A (1 - cos 2 pi t / P), from rest at t = 0.
  int wiggle_axis = -1;
  double amplitude = 0, period = 0;
  //! The wall's time when an engine starts with it (a continued run gives the time the last one
  //! ended, so the wall keeps its place and phase); `clock`, if set, gives it instead when the
  //! engine is made (an adapter whose engines are remade within a run: LAMMPS).
  double time = 0;
  std::function<double()> clock;
  WallLaw law;
  std::string source;  //!< how messages name it, e.g. `--wall 2 "cylinder z 0 0 5"`

  //! The geometry moves (translate, wiggle): detection follows it.
  bool geometry_moves() const { return dot(translate, translate) != 0 || wiggle_axis >= 0; }
  bool moving() const { return omega != 0 || dot(surface_velocity, surface_velocity) != 0 || geometry_moves(); }
  //! The wall's time when an engine is made with it.
  double start_time() const { return clock ? clock() : time; }
  //! Outside a cylinder or sphere: an obstacle, which a path can touch and leave within a step.
  bool convex_obstacle() const { return !inside && (kind == ShapeKind::Cylinder || kind == ShapeKind::Sphere); }
};

//! The kind's word ("plane", "cylinder", "sphere", "cone").
const char* shape_kind_name(ShapeKind k);

//! Parses a wall from the words every face uses: a shape, its numbers, then keywords in any
//! order (docs/cli.md):
//!   plane PX PY PZ NX NY NZ              the normal points to the spheres' side
//!   cylinder AXIS C1 C2 R                the axis through (C1, C2), the other two coordinates in order
//!   sphere CX CY CZ R
//!   cone AXIS C1 C2 LO HI RLO RHI        radii RLO at LO and RHI at HI along AXIS; open ends
//!   inside | outside                     cylinder, sphere (inside by default)
//!   bounds LO HI                         cylinder: an open tube from LO to HI along its axis
//!   rotate W                             cylinder, sphere, cone: surface turning about +axis;
//!                                        plane: about its normal through its point
//!   axis x|y|z                           sphere: the axis it rotates about (z by default)
//!   shear VX VY VZ                       plane: surface velocity in the plane
//!   translate VX VY VZ                   the whole wall moves at this velocity
//!   wiggle x|y|z A P                     the wall oscillates: A (1 - cos 2 pi t / P) along the axis
//!                                        (a plane; a cylinder along its own axis, unbounded)
//!   time T                               the wall's time at the run's start (0 by default)
//!   restitution E, tangential_restitution B, friction MU   the wall's law
//! Throws InputError naming `source` and the word for anything else (an unknown word, a missing
//! or non-numeric value, a keyword the shape does not take, a keyword twice).
WallShape parse_wall_shape(const std::string& spec, const std::string& source);

//! The wall in the words parse_wall_shape() reads (numbers as format_number writes them).
std::string describe(const WallShape& w);

//! Throws InputError naming the wall's source and the value: a zero or non-finite normal, a
//! radius <= 0, cone radii < 0 or both 0, bounds with lo >= hi, a non-finite number, a shear
//! velocity with a part along the normal, a motion the shape does not take (wiggle: an amplitude
//! < 0, a period <= 0, a cylinder not along its own axis or bounded, a sphere or a cone), or a wall
//! that is not the same along a periodic axis (a plane whose normal has a component there or that
//! rotates, a cylinder along another axis or bounded, a sphere or a cone). Returns the wall with its
//! normal made unit.
WallShape validated_shape(WallShape w, const std::array<bool, 3>& periodic);

//! The signed gap between a sphere of radius a at x and the wall (negative: overlapping), or
//! +infinity where the wall has no surface near it (beyond an open tube's or a cone's ends, or on
//! the far side of their thin shells: a centre more than a beyond the surface).
inline double shape_gap(const WallShape& w, Vec3<double> x, double a) {
  const Vec3<double> r = x - w.point;
  switch (w.kind) {
    case ShapeKind::Plane:
      return dot(r, w.normal) - a;
    case ShapeKind::Sphere: {
      const double d = norm(r);
      return w.inside ? w.radius - a - d : d - w.radius - a;
    }
    case ShapeKind::Cylinder: {
      const double s = x[w.axis];
      if (!(s >= w.lo && s <= w.hi)) return std::numeric_limits<double>::infinity();
      Vec3<double> rho = r;
      rho[w.axis] = 0;
      const double d = norm(rho);
      const double gap = w.inside ? w.radius - a - d : d - w.radius - a;
      // An open tube is a thin shell: a centre beyond it by more than a is on its other side.
      if (gap < -2 * a && (std::isfinite(w.lo) || std::isfinite(w.hi))) return std::numeric_limits<double>::infinity();
      return gap;
    }
    case ShapeKind::Cone: {
      Vec3<double> rho = r;
      rho[w.axis] = 0;
      const double s = x[w.axis], rad = norm(rho);
      const double len = w.hi - w.lo, dr = w.radius_hi - w.radius_lo, l = std::hypot(len, dr);
      const double surface = w.radius_lo + dr * (s - w.lo) / len;
      const double d = (surface - rad) * len / l;  // distance to the cone's line in the meridian plane
      const double foot = s - d * dr / l;          // the contact point's axial coordinate
      // Beyond the open ends, or outside the funnel (a thin shell: the centre beyond it by more
      // than a), there is no wall.
      if (!(foot >= w.lo && foot <= w.hi) || d < -a) return std::numeric_limits<double>::infinity();
      return d - a;
    }
  }
  return std::numeric_limits<double>::infinity();
}

//! The unit normal of the wall at the contact of a sphere at x, pointing to the spheres' side.
inline Vec3<double> shape_normal(const WallShape& w, Vec3<double> x) {
  if (w.kind == ShapeKind::Plane) return w.normal;
  Vec3<double> rho = x - w.point;
  if (w.kind != ShapeKind::Sphere) rho[w.axis] = 0;
  const double d = norm(rho);
  Vec3<double> u{};
  if (d > 0)
    u = (1.0 / d) * rho;
  else
    u[(w.axis + 1) % 3] = 1;  // on the axis: any radial direction
  if (w.kind == ShapeKind::Cone) {
    const double len = w.hi - w.lo, dr = w.radius_hi - w.radius_lo, l = std::hypot(len, dr);
    Vec3<double> n = (-len / l) * u;
    n[w.axis] = dr / l;
    return n;
  }
  return w.inside ? -u : u;
}

//! The wall surface's velocity at point p (a rotating wall turns about its axis through `point`;
//! a plane about its normal, plus its shear).
inline Vec3<double> shape_surface_velocity(const WallShape& w, Vec3<double> p) {
  if (w.kind == ShapeKind::Plane)
    return w.omega == 0 ? w.surface_velocity : w.surface_velocity + w.omega * cross(w.normal, p - w.point);
  if (w.omega == 0) return {};
  Vec3<double> e{};
  e[w.axis] = w.omega;
  return cross(e, p - w.point);
}

//! How far wall w's geometry has moved at its time t (translate and wiggle).
inline Vec3<double> shape_displacement(const WallShape& w, double t) {
  Vec3<double> d = t * w.translate;
  const double omega = 2 * M_PI / w.period;
  if (w.wiggle_axis >= 0) d[w.wiggle_axis] += w.amplitude - w.amplitude * std::cos(omega * t);
  return d;
}
//! The velocity of wall w's geometry at its time t.
inline Vec3<double> shape_motion_velocity(const WallShape& w, double t) {
  Vec3<double> u = w.translate;
  const double omega = 2 * M_PI / w.period;
  if (w.wiggle_axis >= 0) u[w.wiggle_axis] += w.amplitude * omega * std::sin(omega * t);
  return u;
}
//! The acceleration of wall w's geometry at its time t (a wiggle's; 0 otherwise).
inline Vec3<double> shape_motion_acceleration(const WallShape& w, double t) {
  Vec3<double> acc{};
  const double omega = 2 * M_PI / w.period;
  if (w.wiggle_axis >= 0) acc[w.wiggle_axis] = w.amplitude * omega * omega * std::cos(omega * t);
  return acc;
}
//! The gap of a sphere of radius a at x from wall w where it is at its time t.
inline double shape_gap_at(const WallShape& w, double t, Vec3<double> x, double a) {
  return w.geometry_moves() ? shape_gap(w, x - shape_displacement(w, t), a) : shape_gap(w, x, a);
}

struct ParticleSystem;
//! Refuses (InputError) a sphere of `sys` that starts overlapping a wall (a moving one where it
//! is at its start_time()), naming the sphere, the wall and the overlap.
void check_clear_of_shapes(const ParticleSystem& sys, const std::vector<WallShape>& shapes);

//! A wall's totals over a run: its collisions, resting contacts and the work it did on the
//! spheres (0 for a wall at rest).
struct WallShapeTotals {
  std::int64_t collisions = 0, resting_contacts = 0;
  double work = 0;
};

}  // namespace hardsphere
