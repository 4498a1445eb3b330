#include "region_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "domain.h"
#include "error.h"
#include "hardsphere/format.hpp"
#include "lammps.h"
#include "region.h"
#include "update.h"

namespace LAMMPS_NS {

namespace {

using V = hardsphere::Vec3<double>;
using hardsphere::ShapeKind;
using hardsphere::WallShape;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kChecks = 20000;  // random points each rebuilt solid is checked at

Region *find_region(LAMMPS *lmp, const std::string &id) {
#if HS_LAMMPS_VERSION < 20220623  // Domain::get_region_by_id came with the region rework
  const int i = lmp->domain->find_region(id);
  return i < 0 ? nullptr : lmp->domain->regions[i];
#else
  return lmp->domain->get_region_by_id(id);
#endif
}

std::vector<Region *> union_members(LAMMPS *lmp, Region *r) {
  std::vector<Region *> out;
  for (int i = 0; i < r->nregion; i++) {
#if HS_LAMMPS_VERSION < 20220623
    out.push_back(lmp->domain->regions[r->list[i]]);
#else
    (void)lmp;
    out.push_back(r->reglist[i]);
#endif
  }
  return out;
}

std::string num(double v) { return hardsphere::format_number(v); }
V unit(int d, double s = 1) {
  V e{};
  e[d] = s;
  return e;
}

//! A solid rebuilt from a region's inside() test, in box units.
struct Solid {
  ShapeKind kind = ShapeKind::Plane;
  bool block = false;
  int axis = 2;
  V c{};                                            // sphere: centre; cylinder, cone: axis point; plane: a point on it
  V n{0, 0, 1};                                     // plane: towards its inside
  V lo{-kInf, -kInf, -kInf}, hi{kInf, kInf, kInf};  // block faces; cylinder, cone: [axis]
  double r = 0, rlo = 0, rhi = 0;
  //! Positive inside, negative outside; its size at most the distance to the surface.
  double depth(V p) const {
    if (block) {
      double m = kInf;
      for (int d = 0; d < 3; d++) m = std::min({m, p[d] - lo[d], hi[d] - p[d]});
      return m;
    }
    V rho = p - c;
    if (kind == ShapeKind::Plane) return dot(rho, n);
    if (kind == ShapeKind::Sphere) return r - norm(rho);
    const double s = p[axis];
    rho[axis] = 0;
    const double along = std::min(s - lo[axis], hi[axis] - s);
    if (kind == ShapeKind::Cylinder) return std::min(r - norm(rho), along);
    const double len = hi[axis] - lo[axis];
    return std::min((rlo + (s - lo[axis]) * (rhi - rlo) / len - norm(rho)) * len / std::hypot(len, rhi - rlo), along);
  }
  std::string text() const {
    const char *axes = "xyz";
    if (block)
      return "block " + num(lo.x) + " " + num(hi.x) + " " + num(lo.y) + " " + num(hi.y) + " " + num(lo.z) + " " +
             num(hi.z);
    if (kind == ShapeKind::Plane)
      return "plane " + num(c.x) + " " + num(c.y) + " " + num(c.z) + " " + num(n.x) + " " + num(n.y) + " " + num(n.z);
    if (kind == ShapeKind::Sphere) return "sphere " + num(c.x) + " " + num(c.y) + " " + num(c.z) + " " + num(r);
    const int b = axis == 0 ? 1 : 0, e = axis == 2 ? 1 : 2;
    const std::string head = std::string(kind == ShapeKind::Cylinder ? "cylinder " : "cone ") + axes[axis] + " " +
                             num(c[b]) + " " + num(c[e]) + " ";
    if (kind == ShapeKind::Cylinder) return head + num(r) + " " + num(lo[axis]) + " " + num(hi[axis]);
    return head + num(rlo) + " " + num(rhi) + " " + num(lo[axis]) + " " + num(hi[axis]);
  }
};

//! One region's inside() test, probed along coordinate lines in box units.
class Probe {
 public:
  Probe(LAMMPS *lmp, Region *r, std::string name) : lmp_(lmp), r_(r), name_(std::move(name)) {
    for (int d = 0; d < 3; d++) {
      box_lo_[d] = lmp->domain->boxlo[d], box_hi_[d] = lmp->domain->boxhi[d];
      span_ = std::max(span_, box_hi_[d] - box_lo_[d]);
    }
  }
  bool in(V p) const { return r_->inside(p.x, p.y, p.z) != 0; }
  double span() const { return span_; }
  [[noreturn]] void fail(const std::string &what) const { lmp_->error->all(FLERR, name_ + ": " + what); }

  //! The last coordinate along axis d from p (inside) towards sgn that is inside (a flat face's
  //! coordinate exactly: bisection on the coordinate itself), or sgn inf beyond 4 box lengths.
  double edge(V p, int d, int sgn) const {
    double a = p[d], step = span_ / 64;
    double b = a + sgn * step;
    for (;;) {
      V q = p;
      q[d] = b;
      if (!in(q)) break;
      a = b, step *= 2, b = a + sgn * step;
      if (std::abs(b - 0.5 * (box_lo_[d] + box_hi_[d])) > 4 * span_) return sgn * kInf;
    }
    for (;;) {
      const double mid = a + 0.5 * (b - a);
      if (mid == a || mid == b) return a;
      V q = p;
      q[d] = mid;
      (in(q) ? a : b) = mid;
    }
  }
  double middle(V p, int d, double *half = nullptr) const {
    const double lo = edge(p, d, -1), hi = edge(p, d, 1);
    if (!std::isfinite(lo) || !std::isfinite(hi)) return kInf;
    if (half) *half = 0.5 * (hi - lo);
    return 0.5 * (lo + hi);
  }
  //! A point inside: the box's centre, else the first of fixed pseudo-random points (the same
  //! on every rank).
  V inside_point() const {
    V p = 0.5 * (box_lo_ + box_hi_);
    std::mt19937_64 rng(2718281828);
    for (int k = 0; k < 1000000 && !in(p); k++) p = random(rng, 1.0);
    if (!in(p)) fail("no point of the region found within a box length of the box: give it a volume there");
    return p;
  }
  V random(std::mt19937_64 &rng, double margin) const {
    std::uniform_real_distribution<double> u(0, 1);
    V p{};
    for (int d = 0; d < 3; d++)
      p[d] = box_lo_[d] - margin * span_ + u(rng) * (box_hi_[d] - box_lo_[d] + 2 * margin * span_);
    return p;
  }
  //! The first of kChecks pseudo-random points around the box where the solid and LAMMPS
  //! disagree by more than rounding; `quick`: a tenth of them.
  bool agrees(const Solid &s, bool quick, V *where = nullptr) const {
    std::mt19937_64 rng(31415926);
    const double tol = 1e-9 * (span_ + norm(s.c));
    for (int k = 0; k < (quick ? kChecks / 10 : kChecks); k++) {
      const V p = random(rng, k % 2 ? 0.1 : 1.0);
      const double depth = s.depth(p);
      if (std::abs(depth) < tol) continue;
      if ((depth > 0) != in(p)) {
        if (where) *where = p;
        return false;
      }
    }
    return true;
  }

 private:
  LAMMPS *lmp_;
  Region *r_;
  std::string name_;
  V box_lo_{}, box_hi_{};
  double span_ = 0;
};

Solid block_solid(const Probe &pr) {
  Solid s;
  s.block = true;
  const V p = pr.inside_point();
  for (int d = 0; d < 3; d++) s.lo[d] = pr.edge(p, d, -1), s.hi[d] = pr.edge(p, d, 1);
  return s;
}

Solid sphere_solid(const Probe &pr) {
  Solid s;
  s.kind = ShapeKind::Sphere;
  V p = pr.inside_point();
  for (int d = 0; d < 3; d++) p[d] = pr.middle(p, d, &s.r);
  s.c = p;
  return s;
}

//! A cylinder or cone along `axis`, or false if the region is not one.
bool round_solid(const Probe &pr, ShapeKind kind, int axis, Solid &s) {
  s = Solid{};
  s.kind = kind, s.axis = axis;
  const int b = axis == 0 ? 1 : 0, e = axis == 2 ? 1 : 2;
  V p = pr.inside_point();
  p[b] = pr.middle(p, b);
  p[e] = pr.middle(p, e, &s.r);
  if (!std::isfinite(p[b]) || !std::isfinite(p[e])) return false;
  s.c = p;
  s.c[axis] = 0;
  s.lo[axis] = pr.edge(p, axis, -1), s.hi[axis] = pr.edge(p, axis, 1);
  double rb = 0;
  if (!std::isfinite(pr.middle(p, b, &rb)) || std::abs(rb - s.r) > 1e-9 * pr.span()) return false;
  if (kind == ShapeKind::Cone) {
    if (!std::isfinite(s.lo[axis]) || !std::isfinite(s.hi[axis])) return false;
    const auto radius_at = [&](double at) {
      V q = s.c;
      q[axis] = at;
      double r = 0;
      if (pr.in(q)) pr.middle(q, b, &r);
      return r;
    };
    s.rlo = radius_at(s.lo[axis]), s.rhi = radius_at(s.hi[axis]);
  }
  return pr.agrees(s, true);
}

Solid plane_solid(LAMMPS *lmp, Region *r, const Probe &pr) {
  Solid s;
  V p = pr.inside_point();
  // A point off the plane: the contact's vector from the plane to it is along the normal.
  for (int k = 1; k < 64; k++) {
    double x[3] = {p.x, p.y, p.z};
    int n = r->surface_interior(x, 1e300);
    double sign = 1;
    if (n == 0) n = r->surface_exterior(x, 1e300), sign = -1;
    if (n > 0 && r->contact[0].r > 0) {
      const V del{r->contact[0].delx, r->contact[0].dely, r->contact[0].delz};
      s.n = (sign / norm(del)) * del;
      s.c = p - del;
      return s;
    }
    p = p + V{0.37 * k, 0.61 * k, 0.83 * k};
  }
  (void)lmp;
  pr.fail("its plane could not be found from its surface contacts");
}

//! Where LAMMPS turns region r about: set_velocity() at a made-up angle rate of 1 gives its
//! axis (as given: LAMMPS's contact velocity is rate x axis) and point; every field it touches
//! is restored.
void turning_axis(LAMMPS *lmp, Region *r, V &axis, V &point) {
  Update *u = lmp->update;
  const bigint step = u->ntimestep;
  const int vel_step = r->vel_timestep;
  const double theta = r->theta, prev = r->prev[3];
  const V omega{r->omega[0], r->omega[1], r->omega[2]}, rpoint{r->rpoint[0], r->rpoint[1], r->rpoint[2]};
  u->ntimestep = step + 1;
  r->vel_timestep = -1;
  r->prev[3] = 0, r->theta = u->dt;
  r->set_velocity();
  axis = {r->omega[0], r->omega[1], r->omega[2]};
  point = {r->rpoint[0], r->rpoint[1], r->rpoint[2]};
  u->ntimestep = step;
  r->vel_timestep = vel_step;
  r->theta = theta, r->prev[3] = prev;
  for (int d = 0; d < 3; d++) r->omega[d] = omega[d], r->rpoint[d] = rpoint[d];
}

class Reader {
 public:
  Reader(LAMMPS *lmp, const hardsphere::WallLaw &law, std::string name)
      : lmp_(lmp), law_(law), name_(std::move(name)) {}
  [[noreturn]] void fail(const std::string &what) const { lmp_->error->all(FLERR, name_ + ": " + what); }

  RegionWalls read(Region *r) {
    const std::string style = r->style, id = r->id;
    if (style == "union") {
      if (r->dynamic || r->moveflag || r->rotateflag)
        fail("region " + id +
             " (union) moves as a whole ('move'/'rotate' on the union), which its walls do not "
             "follow: give 'rotate' to each piece, about the piece's own axis");
      if (!r->interior)
        fail("region " + id +
             " is a union with 'side out': the spheres would be outside its pieces, whose faces "
             "are finite; use 'side in'");
      const std::vector<Region *> pieces = union_members(lmp_, r);
      std::vector<Solid> solids;
      for (Region *m : pieces) {
        if (!m->interior)
          fail("region " + std::string(m->id) + " in union " + id +
               " has 'side out', whose faces are finite: give its pieces 'side in'");
        solids.push_back(primitive(m, id));
      }
      check_union(pieces, solids, id);
      return out_;
    }
    primitive(r, "");
    return out_;
  }

 private:
  Solid primitive(Region *r, const std::string &in_union) {
    const std::string style = r->style, id = r->id;
    const std::string what = "region " + id + (in_union.empty() ? "" : " (in union " + in_union + ")");
    if (style == "intersect")
      fail(what +
           " is an intersect, whose surface is parts of its pieces' surfaces, which fix "
           "wall/hardsphere/region cannot follow exactly: build the walls as a block, cylinder, cone, sphere or "
           "plane region, a union of them, or several fixes");
    if (style == "union") fail(what + " is a union inside a union: give its pieces to one union");
    if (style != "block" && style != "sphere" && style != "cylinder" && style != "cone" && style != "plane")
      fail(what + " has style '" + style +
           "', which fix wall/hardsphere/region does not read: use block, sphere, cylinder, cone or plane regions, or "
           "a union of them");
    if (r->varshape)
      fail(what +
           " changes its size with a variable during the run, which hard-sphere walls do not follow: give "
           "its sizes as numbers");
    if (r->moveflag)
      fail(what +
           " translates ('move'), which fix wall/hardsphere/region does not follow: use a region at rest "
           "or one turning ('rotate') about its own axis");
    if (r->rotateflag && style == "block")
      fail(what +
           " is a block turning ('rotate'), whose faces move: fix wall/hardsphere/region turns only "
           "cylinders, cones and spheres about their axis and planes about their normal");
    const Probe pr(lmp_, r, name_ + ": " + what);
    Solid s;
    if (style == "block") {
      s = block_solid(pr);
    } else if (style == "sphere") {
      s = sphere_solid(pr);
    } else if (style == "plane") {
      s = plane_solid(lmp_, r, pr);
    } else {
      const ShapeKind kind = style == "cylinder" ? ShapeKind::Cylinder : ShapeKind::Cone;
      bool found = false;
      for (int a = 0; a < 3 && !found; a++) found = round_solid(pr, kind, a, s);
      if (!found) fail(what + ": its " + style + " along x, y or z could not be rebuilt from its inside() test");
    }
    V where{};
    if (!pr.agrees(s, false, &where))
      fail(what + " is not the " + s.text() + " rebuilt from it (they disagree at " + num(where.x) + " " +
           num(where.y) + " " + num(where.z) + "): refused rather than approximated");
    add_walls(r, s, what);
    return s;
  }

  WallShape base(const std::string &what) const {
    WallShape w;
    w.law = law_;
    w.source = name_ + " " + what;
    return w;
  }
  void add_plane(V point, V normal, const std::string &what) {
    WallShape w = base(what);
    w.kind = ShapeKind::Plane, w.point = point, w.normal = normal;
    out_.shapes.push_back(w);
  }

  //! The solid's faces as walls, spheres on the region's side; a rotating region's turn.
  void add_walls(Region *r, const Solid &s, const std::string &what) {
    const std::size_t first = out_.shapes.size();
    const bool out = !r->interior;
    const auto open = [&](int f) { return r->openflag && r->open_faces[f]; };
    const int a = s.axis;
    if (s.block) {
      if (out) fail(what + " has 'side out', whose faces are finite: use 'side in' (or planes)");
      for (int d = 0; d < 3; d++) {
        if (std::isfinite(s.lo[d]) && !open(2 * d)) add_plane(unit(d, s.lo[d]), unit(d), what);
        if (std::isfinite(s.hi[d]) && !open(2 * d + 1)) add_plane(unit(d, s.hi[d]), unit(d, -1), what);
      }
    } else if (s.kind == ShapeKind::Plane) {
      add_plane(s.c, out ? -1.0 * s.n : s.n, what);
    } else if (s.kind == ShapeKind::Sphere) {
      WallShape w = base(what);
      w.kind = ShapeKind::Sphere, w.point = s.c, w.radius = s.r, w.inside = !out;
      out_.shapes.push_back(w);
    } else {
      const bool bounded = std::isfinite(s.lo[a]) || std::isfinite(s.hi[a]);
      if (out && (s.kind == ShapeKind::Cone || bounded))
        fail(what +
             " has 'side out', whose faces are finite: use 'side in', or a cylinder unbounded along its "
             "axis (INF) for an obstacle");
      if (!open(2)) {
        WallShape w = base(what);
        w.kind = s.kind, w.axis = a, w.point = s.c, w.inside = !out, w.radius = s.r;
        w.lo = s.lo[a], w.hi = s.hi[a], w.radius_lo = s.rlo, w.radius_hi = s.rhi;
        out_.shapes.push_back(w);
      }
      V cap = s.c;
      cap[a] = s.lo[a];
      const bool cone = s.kind == ShapeKind::Cone;
      if (std::isfinite(s.lo[a]) && !open(0) && !(cone && s.rlo == 0)) add_plane(cap, unit(a), what);
      cap[a] = s.hi[a];
      if (std::isfinite(s.hi[a]) && !open(1) && !(cone && s.rhi == 0)) add_plane(cap, unit(a, -1), what);
    }
    if (r->rotateflag) add_turn(r, s, first, what);
  }

  void add_turn(Region *r, const Solid &s, std::size_t first, const std::string &what) {
    V axis{}, point{};
    turning_axis(lmp_, r, axis, point);
    const double tol = 1e-9 * (norm(s.c) + norm(point) + 1);
    RegionTurn turn;
    turn.region = r;
    const auto off_axis = [&](const std::string &own) {
      fail(what + " turns about the axis " + num(axis.x) + " " + num(axis.y) + " " + num(axis.z) + " through " +
           num(point.x) + " " + num(point.y) + " " + num(point.z) +
           ", which moves its surface: fix wall/hardsphere/region turns a region only about " + own);
    };
    if (s.kind == ShapeKind::Plane) {
      if (norm(cross(axis, s.n)) > 1e-12 * norm(axis)) off_axis("its normal (a plane)");
    } else if (s.kind == ShapeKind::Sphere) {
      if (norm(point - s.c) > tol) off_axis("an axis through its centre (a sphere)");
    } else {
      V off = point - s.c;
      off[s.axis] = 0;
      if (norm(off) > tol || axis[(s.axis + 1) % 3] != 0 || axis[(s.axis + 2) % 3] != 0)
        off_axis("its own axis (a cylinder or cone)");
    }
    int sphere_axis = -1;
    for (int d = 0; d < 3; d++)
      if (axis[(d + 1) % 3] == 0 && axis[(d + 2) % 3] == 0) sphere_axis = d;
    if (s.kind == ShapeKind::Sphere && sphere_axis < 0) off_axis("x, y or z through its centre (a sphere)");
    for (std::size_t k = first; k < out_.shapes.size(); k++) {
      WallShape &w = out_.shapes[k];
      double scale = 0;
      if (w.kind == ShapeKind::Plane) {
        scale = dot(axis, w.normal);
        w.point = point - dot(point - w.point, w.normal) * w.normal;  // the axis's foot on the plane
      } else if (w.kind == ShapeKind::Sphere) {
        w.axis = sphere_axis;
        w.point = point;
        scale = axis[sphere_axis];
      } else {
        const double along = w.point[w.axis];
        w.point = point;  // LAMMPS's own axis point (the rebuilt one agrees to rounding)
        w.point[w.axis] = along;
        scale = axis[w.axis];
      }
      turn.shapes.push_back(k);
      turn.scales.push_back(scale);
    }
    out_.turns.push_back(turn);
  }

  //! A union's surface is its pieces' surfaces where they are outside the other pieces
  //! (LAMMPS's RegUnion::surface_interior): the walls are the pieces' only when no closed face of
  //! one lies inside another. Points on each face, from its surface contacts, are checked.
  void check_union(const std::vector<Region *> &pieces, const std::vector<Solid> &solids, const std::string &id) {
    std::mt19937_64 rng(1414213562);
    for (std::size_t i = 0; i < pieces.size(); i++) {
      const Probe pr(lmp_, pieces[i], name_);
      for (int k = 0; k < 4000; k++) {
        const V p = pr.random(rng, 0.1);
        if (!(solids[i].depth(p) > 0)) continue;
        double x[3] = {p.x, p.y, p.z};
        const int n = pieces[i]->surface_interior(x, 1e300);
        for (int c = 0; c < n; c++) {
          const V del{pieces[i]->contact[c].delx, pieces[i]->contact[c].dely, pieces[i]->contact[c].delz};
          const double len = norm(del);
          if (!(len > 0)) continue;
          const V beyond = p - (1 + 1e-6 * pr.span() / len) * del;  // just outside piece i's face
          for (std::size_t j = 0; j < pieces.size(); j++)
            if (j != i && solids[j].depth(beyond) > 1e-9 * pr.span())
              fail("region " + id + " is a union whose piece " + pieces[i]->id + " has a face inside piece " +
                   pieces[j]->id + " (near " + num(beyond.x) + " " + num(beyond.y) + " " + num(beyond.z) +
                   "), which the union's surface leaves out: open that face ('open'), or make the pieces meet "
                   "face to face (a funnel: a cone and a cylinder of the cone's end radius)");
        }
      }
    }
  }

  LAMMPS *lmp_;
  hardsphere::WallLaw law_;
  std::string name_;
  RegionWalls out_;
};

}  // namespace

RegionWalls region_walls(LAMMPS *lmp, const std::string &id, const hardsphere::WallLaw &law, const std::string &name) {
  Region *r = find_region(lmp, id);
  if (!r) lmp->error->all(FLERR, name + ": region " + id + " does not exist (define it with the region command first)");
  return Reader(lmp, law, name).read(r);
}

double region_turn_rate(LAMMPS *lmp, Region *region) {
  // Called in initial_integrate, where ntimestep is already the step being taken: the step
  // runs from ntimestep - 1 to ntimestep, the interval LAMMPS's set_velocity() takes at its end.
  Update *u = lmp->update;
  const bigint step = u->ntimestep;
  u->ntimestep = step - 1;
  region->pretransform();
  const double before = region->theta;
  u->ntimestep = step;
  region->pretransform();
  return (region->theta - before) / u->dt;
}

}  // namespace LAMMPS_NS
