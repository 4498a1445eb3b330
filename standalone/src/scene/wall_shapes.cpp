//! Shaped walls: their words (parse_wall_shape, describe) and their validation.
#include "hardsphere/wall_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/particles.hpp"

namespace hardsphere {

const char* shape_kind_name(ShapeKind k) {
  switch (k) {
    case ShapeKind::Plane:
      return "plane";
    case ShapeKind::Cylinder:
      return "cylinder";
    case ShapeKind::Sphere:
      return "sphere";
    case ShapeKind::Cone:
      return "cone";
  }
  return "?";
}

namespace {

//! The words of one spec, read in order; every refusal names the source and the word.
class Words {
 public:
  Words(const std::string& spec, const std::string& source) : source_(source) {
    std::istringstream in(spec);
    for (std::string w; in >> w;) words_.push_back(w);
  }
  bool done() const { return next_ >= words_.size(); }
  std::string word(const std::string& what) {
    if (done()) fail("expects " + what + " at its end");
    return words_[next_++];
  }
  double number(const std::string& what) {
    const std::string w = word(what);
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (w.empty() || *end != '\0') fail("expects " + what + ", got '" + w + "'");
    return v;
  }
  int axis(const std::string& what) {
    const std::string w = word(what);
    if (w == "x") return 0;
    if (w == "y") return 1;
    if (w == "z") return 2;
    fail("expects " + what + " (x, y or z), got '" + w + "'");
    return 0;
  }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(source_ + ": " + what); }

 private:
  std::vector<std::string> words_;
  std::size_t next_ = 0;
  std::string source_;
};

int first_other(int axis) { return axis == 0 ? 1 : 0; }
int second_other(int axis) { return axis == 2 ? 1 : 2; }
//! The two coordinates other than the axis, in order (z: x y).
void set_axis_point(WallShape& w, double c1, double c2) {
  w.point = {};
  w.point[first_other(w.axis)] = c1;
  w.point[second_other(w.axis)] = c2;
}

std::string num(double v) { return format_number(v); }

}  // namespace

WallShape parse_wall_shape(const std::string& spec, const std::string& source) {
  Words in(spec, source);
  WallShape w;
  w.source = source;
  const std::string kind = in.word("a shape (plane, cylinder, sphere or cone)");
  if (kind == "plane") {
    w.kind = ShapeKind::Plane;
    for (int d = 0; d < 3; ++d) w.point[d] = in.number("the plane's point PX PY PZ");
    for (int d = 0; d < 3; ++d) w.normal[d] = in.number("the plane's normal NX NY NZ");
  } else if (kind == "cylinder") {
    w.kind = ShapeKind::Cylinder;
    w.axis = in.axis("the cylinder's axis");
    const double c1 = in.number("the axis's coordinates C1 C2"), c2 = in.number("the axis's coordinates C1 C2");
    set_axis_point(w, c1, c2);
    w.radius = in.number("the cylinder's radius");
  } else if (kind == "sphere") {
    w.kind = ShapeKind::Sphere;
    for (int d = 0; d < 3; ++d) w.point[d] = in.number("the sphere's centre CX CY CZ");
    w.radius = in.number("the sphere's radius");
  } else if (kind == "cone") {
    w.kind = ShapeKind::Cone;
    w.axis = in.axis("the cone's axis");
    const double c1 = in.number("the axis's coordinates C1 C2"), c2 = in.number("the axis's coordinates C1 C2");
    set_axis_point(w, c1, c2);
    w.lo = in.number("the cone's axial extent LO HI");
    w.hi = in.number("the cone's axial extent LO HI");
    w.radius_lo = in.number("the cone's radii RLO RHI");
    w.radius_hi = in.number("the cone's radii RLO RHI");
  } else {
    in.fail("unknown shape '" + kind + "' (expected plane, cylinder, sphere or cone)");
  }
  std::set<std::string> seen;
  while (!in.done()) {
    const std::string key = in.word("a keyword");
    const std::string group = key == "outside" ? "inside" : key;
    if (!seen.insert(group).second) in.fail("'" + key + "' given twice");
    const auto only = [&](bool ok, const std::string& shapes) {
      if (!ok) in.fail("'" + key + "' applies to " + shapes + ", not a " + kind);
    };
    if (key == "inside" || key == "outside") {
      only(w.kind == ShapeKind::Cylinder || w.kind == ShapeKind::Sphere, "a cylinder or a sphere");
      w.inside = key == "inside";
    } else if (key == "bounds") {
      only(w.kind == ShapeKind::Cylinder, "a cylinder");
      w.lo = in.number("bounds LO HI");
      w.hi = in.number("bounds LO HI");
    } else if (key == "rotate") {
      w.omega = in.number("rotate W (angular velocity about +axis)");
    } else if (key == "axis") {
      only(w.kind == ShapeKind::Sphere, "a sphere (its rotation's axis)");
      w.axis = in.axis("the rotation's axis");
    } else if (key == "shear") {
      only(w.kind == ShapeKind::Plane, "a plane (round walls take rotate)");
      for (int d = 0; d < 3; ++d) w.surface_velocity[d] = in.number("shear VX VY VZ");
    } else if (key == "translate") {
      for (int d = 0; d < 3; ++d) w.translate[d] = in.number("translate VX VY VZ");
    } else if (key == "wiggle") {
      w.wiggle_axis = in.axis("wiggle's axis");
      w.amplitude = in.number("wiggle's amplitude A");
      w.period = in.number("wiggle's period P");
    } else if (key == "time") {
      w.time = in.number("time T (the wall's time at the run's start)");
    } else if (key == "restitution") {
      w.law.restitution = in.number("restitution E");
    } else if (key == "tangential_restitution") {
      w.law.tangential_restitution = in.number("tangential_restitution B");
    } else if (key == "friction") {
      w.law.friction = in.number("friction MU");
    } else {
      in.fail("unknown keyword '" + key +
              "' (expected inside, outside, bounds, rotate, axis, shear, translate, wiggle, time, restitution, "
              "tangential_restitution or friction)");
    }
  }
  return w;
}

std::string describe(const WallShape& w) {
  std::ostringstream o;
  const char* axes = "xyz";
  o << shape_kind_name(w.kind);
  switch (w.kind) {
    case ShapeKind::Plane:
      o << ' ' << num(w.point.x) << ' ' << num(w.point.y) << ' ' << num(w.point.z) << ' ' << num(w.normal.x) << ' '
        << num(w.normal.y) << ' ' << num(w.normal.z);
      break;
    case ShapeKind::Cylinder:
      o << ' ' << axes[w.axis] << ' ' << num(w.point[first_other(w.axis)]) << ' ' << num(w.point[second_other(w.axis)])
        << ' ' << num(w.radius) << (w.inside ? " inside" : " outside");
      if (std::isfinite(w.lo) || std::isfinite(w.hi)) o << " bounds " << num(w.lo) << ' ' << num(w.hi);
      break;
    case ShapeKind::Sphere:
      o << ' ' << num(w.point.x) << ' ' << num(w.point.y) << ' ' << num(w.point.z) << ' ' << num(w.radius)
        << (w.inside ? " inside" : " outside");
      if (w.omega != 0) o << " axis " << axes[w.axis];
      break;
    case ShapeKind::Cone:
      o << ' ' << axes[w.axis] << ' ' << num(w.point[first_other(w.axis)]) << ' ' << num(w.point[second_other(w.axis)])
        << ' ' << num(w.lo) << ' ' << num(w.hi) << ' ' << num(w.radius_lo) << ' ' << num(w.radius_hi);
      break;
  }
  if (w.omega != 0) o << " rotate " << num(w.omega);
  if (dot(w.surface_velocity, w.surface_velocity) != 0)
    o << " shear " << num(w.surface_velocity.x) << ' ' << num(w.surface_velocity.y) << ' ' << num(w.surface_velocity.z);
  if (dot(w.translate, w.translate) != 0)
    o << " translate " << num(w.translate.x) << ' ' << num(w.translate.y) << ' ' << num(w.translate.z);
  if (w.wiggle_axis >= 0) o << " wiggle " << axes[w.wiggle_axis] << ' ' << num(w.amplitude) << ' ' << num(w.period);
  if (w.time != 0) o << " time " << num(w.time);
  o << " restitution " << num(w.law.restitution);
  if (w.law.tangential_restitution) o << " tangential_restitution " << num(*w.law.tangential_restitution);
  if (w.law.friction) o << " friction " << num(*w.law.friction);
  return o.str();
}

WallShape validated_shape(WallShape w, const std::array<bool, 3>& periodic) {
  const auto fail = [&](const std::string& what) { throw InputError(w.source + ": " + what); };
  const auto finite = [&](double v, const std::string& what) {
    if (!std::isfinite(v)) fail(what + " " + num(v) + " must be finite");
  };
  for (int d = 0; d < 3; ++d) finite(w.point[d], "point coordinate");
  if (w.kind == ShapeKind::Plane) {
    for (int d = 0; d < 3; ++d) finite(w.normal[d], "normal component");
    const double n = norm(w.normal);
    if (!(n > 0)) fail("normal 0 0 0 has no direction (give the direction from the wall to the spheres)");
    w.normal = (1.0 / n) * w.normal;
    for (int d = 0; d < 3; ++d) finite(w.surface_velocity[d], "shear component");
    const double along = dot(w.surface_velocity, w.normal);
    if (std::abs(along) > 1e-12 * norm(w.surface_velocity))
      fail("shear " + num(w.surface_velocity.x) + " " + num(w.surface_velocity.y) + " " + num(w.surface_velocity.z) +
           " has a part " + num(along) +
           " along the normal: a shear moves the surface in its plane (a plane moving along its normal is not "
           "supported)");
    for (int d = 0; d < 3; ++d)
      if (periodic[std::size_t(d)] && w.normal[d] != 0)
        fail(std::string("the plane's normal has a component along periodic axis ") + "xyz"[d] +
             ": a wall across a periodic axis has no meaning; give that axis walls or a normal without it");
    // A turning plate's surface velocity grows with the distance from its axis: not periodic.
    for (int d = 0; d < 3; ++d)
      if (periodic[std::size_t(d)] && w.omega != 0)
        fail(std::string("periodic axis ") + "xyz"[d] +
             " runs along the rotating plane, whose surface velocity is not periodic: give that axis walls");
  }
  if (w.kind == ShapeKind::Cylinder || w.kind == ShapeKind::Sphere) {
    finite(w.radius, "radius");
    if (!(w.radius > 0)) fail("radius " + num(w.radius) + " must be > 0");
  }
  if (w.kind == ShapeKind::Cylinder) {
    if (!(w.lo < w.hi) || std::isnan(w.lo) || std::isnan(w.hi))
      fail("bounds " + num(w.lo) + " " + num(w.hi) + " must have LO < HI");
    for (int d = 0; d < 3; ++d)
      if (periodic[std::size_t(d)] && (d != w.axis || std::isfinite(w.lo) || std::isfinite(w.hi)))
        fail(std::string("periodic axis ") + "xyz"[d] +
             (d == w.axis ? " runs along a bounded cylinder: leave out its bounds or give that axis walls"
                          : " crosses the cylinder: only its own axis may be periodic"));
  }
  if (w.kind == ShapeKind::Sphere || w.kind == ShapeKind::Cone)
    for (int d = 0; d < 3; ++d)
      if (periodic[std::size_t(d)])
        fail(std::string("periodic axis ") + "xyz"[d] + " crosses the " + shape_kind_name(w.kind) +
             ": give that axis walls");
  if (w.kind == ShapeKind::Cone) {
    finite(w.lo, "axial extent LO");
    finite(w.hi, "axial extent HI");
    if (!(w.lo < w.hi)) fail("axial extent " + num(w.lo) + " " + num(w.hi) + " must have LO < HI");
    finite(w.radius_lo, "radius RLO");
    finite(w.radius_hi, "radius RHI");
    if (!(w.radius_lo >= 0 && w.radius_hi >= 0) || (w.radius_lo == 0 && w.radius_hi == 0))
      fail("radii " + num(w.radius_lo) + " " + num(w.radius_hi) + " must be >= 0 and not both 0");
  }
  finite(w.omega, "rotate");
  for (int d = 0; d < 3; ++d) finite(w.translate[d], "translate component");
  finite(w.time, "time");
  if (w.wiggle_axis >= 0) {
    finite(w.amplitude, "wiggle amplitude");
    finite(w.period, "wiggle period");
    if (!(w.amplitude >= 0)) fail("wiggle amplitude " + num(w.amplitude) + " must be >= 0");
    if (!(w.period > 0)) fail("wiggle period " + num(w.period) + " must be > 0");
    // Detection follows a wiggle where the gap's second derivative has a bound it can use: a
    // plane's, or a cylinder's moving along its own unbounded axis (its gap does not change).
    const bool along_tube =
        w.kind == ShapeKind::Cylinder && w.wiggle_axis == w.axis && !std::isfinite(w.lo) && !std::isfinite(w.hi);
    if (w.kind != ShapeKind::Plane && !along_tube)
      fail(std::string("wiggle ") + "xyz"[w.wiggle_axis] + " moves a " + shape_kind_name(w.kind) +
           (w.kind == ShapeKind::Cylinder ? " across its axis or with bounds" : "") +
           ": wiggle takes a plane or an unbounded cylinder along its own axis (translate moves any wall)");
  }
  return w;
}

void check_clear_of_shapes(const ParticleSystem& sys, const std::vector<WallShape>& shapes) {
  for (const WallShape& w : shapes)
    for (std::size_t i = 0; i < sys.size(); ++i) {
      const Vec3<double> x = sys.pos[i];
      const double a = sys.radius[i];
      const double scale = std::max({std::abs(x.x), std::abs(x.y), std::abs(x.z), norm(w.point), w.radius, a});
      const double t = w.geometry_moves() ? w.start_time() : 0.0;
      const double gap = shape_gap_at(w, t, x, a);
      if (gap < -1e-12 * scale)
        throw InputError(atom_origin(sys, i, sys.source.empty() ? "initial state" : sys.source, nullptr) + " (at " +
                         num(x.x) + " " + num(x.y) + " " + num(x.z) + ", radius " + num(a) + ") overlaps " + w.source +
                         (w.geometry_moves() ? " (where it is at its time " + num(t) + ")" : std::string()) + " by " +
                         num(-gap) + ": start every sphere clear of the wall");
    }
}

}  // namespace hardsphere
