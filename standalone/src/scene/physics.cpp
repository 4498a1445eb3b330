#include "hardsphere/physics.hpp"

#include <algorithm>
#include <cmath>

#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"

namespace hardsphere {

std::array<double, 3> without_rounding(std::array<double, 3> g) {
  const double largest = std::max({std::abs(g[0]), std::abs(g[1]), std::abs(g[2])});
  for (double& c : g)
    if (std::abs(c) <= kGravityRounding * largest) c = 0;
  return g;
}

namespace {

//! The option rules: a setting given where it has no effect, and why, with each face's names.
struct OptionRule {
  bool PhysicsGiven::*given;
  std::string PhysicsNames::*name;
  double Physics::*value;
  bool (*has_effect)(const Physics&);
  std::string (*why)(const PhysicsNames&);
};

const OptionRule kOptionRules[] = {
    {&PhysicsGiven::contact_time, &PhysicsNames::contact_time, &Physics::contact_time,
     [](const Physics& p) { return !p.elastic(); },
     [](const PhysicsNames& n) {
       return "has no effect with " + n.restitution + " 1: the TC model makes inelastic collisions elastic, and " +
              "these are elastic already; give a " + n.restitution + " below 1 or leave out " + n.contact_time;
     }},
    {&PhysicsGiven::resting_time, &PhysicsNames::resting_time, &Physics::resting_time,
     [](const Physics& p) { return p.has_gravity(); },
     [](const PhysicsNames& n) {
       return "has no effect without gravity (resting contacts are wall contacts under " + n.gravity + "); give " +
              n.gravity + " or leave out " + n.resting_time;
     }},
    {&PhysicsGiven::friction, &PhysicsNames::friction, &Physics::friction, [](const Physics& p) { return p.rough(); },
     [](const PhysicsNames& n) {
       return "needs a " + n.tangential_restitution + " above -1 as its sticking limit beta0 (smooth spheres " +
              "take no tangential impulse)";
     }},
    {&PhysicsGiven::inertia, &PhysicsNames::inertia, &Physics::inertia, [](const Physics& p) { return p.rough(); },
     [](const PhysicsNames& n) {
       return "has no effect: smooth spheres (" + n.tangential_restitution + " -1) do not rotate; give a " +
              n.tangential_restitution + " above -1";
     }},
};

//! The wall laws' ranges, then what a wall setting needs: a wall on the face it names, rough
//! spheres for a tangential law (see Physics::walls).
void check_walls(Physics& p, const std::array<bool, 3>& periodic, const PhysicsNames& names,
                 const PhysicsGiven& given) {
  for (int f = 0; f < 6; ++f)
    if (given.wall_faces[std::size_t(f)] && periodic[std::size_t(f / 2)])
      throw InputError(std::string("the box has no wall at ") + kFaceNames[std::size_t(f)] + " (axis " + "xyz"[f / 2] +
                       " is periodic): give that face a wall or leave it out of the wall settings");
  if (given.all_walls && periodic == std::array<bool, 3>{true, true, true})
    throw InputError("wall settings have no effect: the box has no walls (every axis is periodic)");
  for (int f = 0; f < 6; ++f)
    if (periodic[std::size_t(f / 2)]) p.walls[std::size_t(f)] = WallLaw{};
  // A value given for every wall is named as given; one of a face with its face.
  const auto label = [&](const std::string& name, int f, double value) {
    return given.all_walls && !given.wall_faces[std::size_t(f)] ? name + " " + format_number(value)
                                                                : names.face_value(name, f, value);
  };
  for (int f = 0; f < 6; ++f) {
    const WallLaw& w = p.walls[std::size_t(f)];
    if (!(w.restitution > 0 && w.restitution <= 1))
      throw InputError(label(names.wall_restitution, f, w.restitution) + " must be in (0, 1] (1: elastic)");
    if (w.tangential_restitution && !(*w.tangential_restitution >= -1 && *w.tangential_restitution <= 1))
      throw InputError(label(names.wall_tangential_restitution, f, *w.tangential_restitution) +
                       " must be in [-1, 1] (-1: smooth, 1: perfectly rough)");
    if (w.friction && !(*w.friction >= 0))
      throw InputError(label(names.wall_friction, f, *w.friction) + " must be >= 0 (infinite: no sliding)");
    // A frictional wall turns the spheres it touches: only rough scenes carry their spins.
    if ((w.tangential_restitution || w.friction) && !p.rough())
      throw InputError(label(w.friction ? names.wall_friction : names.wall_tangential_restitution, f,
                             w.friction ? *w.friction : *w.tangential_restitution) +
                       " needs rough spheres (a " + names.tangential_restitution +
                       " above -1): a wall's tangential impulse turns the spheres, and only rough spheres carry " +
                       "angular velocities");
    if (w.friction && std::isfinite(*w.friction) && p.wall_tangential_restitution(f) == -1)
      throw InputError(label(names.wall_friction, f, *w.friction) + " needs a " + names.wall_tangential_restitution +
                       " above -1 as its sticking limit beta0");
  }
}

//! Each shaped wall's geometry (validated_shape()) and law, named by the wall's source.
void check_shapes(Physics& p, const std::array<bool, 3>& periodic) {
  for (WallShape& shape : p.shapes) {
    shape = validated_shape(shape, periodic);
    const WallLaw& w = shape.law;
    const std::string at = shape.source + ": ";
    if (!(w.restitution > 0 && w.restitution <= 1))
      throw InputError(at + "restitution " + format_number(w.restitution) + " must be in (0, 1] (1: elastic)");
    if (w.tangential_restitution && !(*w.tangential_restitution >= -1 && *w.tangential_restitution <= 1))
      throw InputError(at + "tangential_restitution " + format_number(*w.tangential_restitution) +
                       " must be in [-1, 1] (-1: smooth, 1: perfectly rough)");
    if (w.friction && !(*w.friction >= 0))
      throw InputError(at + "friction " + format_number(*w.friction) + " must be >= 0 (infinite: no sliding)");
    if ((w.tangential_restitution || w.friction) && !p.rough())
      throw InputError(at + (w.friction ? "friction" : "tangential_restitution") +
                       " needs rough spheres (a tangential restitution above -1): a wall's tangential impulse " +
                       "turns the spheres, and only rough spheres carry angular velocities");
    if (w.friction && std::isfinite(*w.friction) && w.tangential_restitution.value_or(p.tangential_restitution) == -1)
      throw InputError(at + "friction " + format_number(*w.friction) +
                       " needs a tangential_restitution above -1 as its sticking limit beta0");
  }
}

}  // namespace

std::string PhysicsNames::face_value(const std::string& name, int face, double value) const {
  return name + " " + kFaceNames[std::size_t(face)] + face_separator + format_number(value);
}

std::array<double, 3> validated_gravity(const std::array<double, 3>& g, const PhysicsNames& names) {
  for (int d = 0; d < 3; ++d)
    if (!std::isfinite(g[std::size_t(d)]))
      throw InputError(names.gravity + " component " + "xyz"[d] + " = " + format_number(g[std::size_t(d)]) +
                       " must be finite");
  return without_rounding(g);
}

Physics validated(Physics p, const std::array<bool, 3>& periodic, const PhysicsNames& names,
                  const PhysicsGiven& given) {
  const std::string e = format_number(p.restitution), tc = format_number(p.contact_time);
  if (!(p.restitution > 0 && p.restitution <= 1))
    throw InputError(names.restitution + " " + e + " must be in (0, 1] (1: elastic)");
  if (!(p.contact_time >= 0 && std::isfinite(p.contact_time)))
    throw InputError(names.contact_time + " " + tc + " must be finite and >= 0");
  if (p.restitution < 1 && p.contact_time == 0)
    throw InputError(names.contact_time + " 0 with " + names.restitution + " " + e +
                     ": an inelastic collapse (infinitely many collisions in finite time) would never end; give " +
                     names.contact_time + " a value > 0");
  if (!(p.resting_time >= 0 && std::isfinite(p.resting_time)))
    throw InputError(names.resting_time + " " + format_number(p.resting_time) + " must be finite and >= 0");
  const std::string beta = format_number(p.tangential_restitution);
  if (!(p.tangential_restitution >= -1 && p.tangential_restitution <= 1))
    throw InputError(names.tangential_restitution + " " + beta +
                     " must be in [-1, 1] (-1: smooth, 1: perfectly rough)");
  if (!(p.friction >= 0))
    throw InputError(names.friction + " " + format_number(p.friction) + " must be >= 0 (infinite: no sliding)");
  if (std::isfinite(p.friction) && !p.rough())
    throw InputError(names.friction + " " + format_number(p.friction) + " needs a " + names.tangential_restitution +
                     " above -1 as its sticking limit beta0");
  if (!(p.inertia > 0 && p.inertia <= 2.0 / 3.0))
    throw InputError(names.inertia + " " + format_number(p.inertia) +
                     " must be in (0, 2/3] (I = q m r^2; 0.4: solid sphere, 2/3: thin shell)");
  p.gravity = validated_gravity(p.gravity, names);
  check_walls(p, periodic, names, given);
  check_shapes(p, periodic);
  if (p.inelastic_walls() && p.contact_time == 0)
    throw InputError(names.contact_time + " 0 with a " + names.wall_restitution +
                     " below 1: an inelastic collapse against a wall would never end; give " + names.contact_time +
                     " a value > 0");
  for (const OptionRule& r : kOptionRules)
    if (given.*r.given && !r.has_effect(p))
      throw InputError(names.*r.name + " " + format_number(p.*r.value) + " " + r.why(names));
  return p;
}

std::string unbounded_flow(const Physics& p, const std::array<bool, 3>& periodic, const PhysicsNames& names) {
  int axis = -1;
  for (int d = 0; d < 3; ++d)
    if (periodic[std::size_t(d)] && p.gravity[std::size_t(d)] != 0 && axis < 0) axis = d;
  if (axis < 0) return "";
  // Pair collisions conserve momentum and smooth walls push along their normals only: the
  // momentum along a periodic axis leaves the spheres through wall friction alone.
  bool frictional_wall = false, lossless = p.elastic();
  for (int f = 0; f < 6; ++f) {
    if (periodic[std::size_t(f / 2)]) continue;
    const double beta = p.wall_tangential_restitution(f), mu = p.wall_friction(f);
    if (p.rough() && beta > -1 && mu > 0) frictional_wall = true;
    if (p.rough() && !(std::abs(beta) == 1 && std::isinf(mu))) lossless = false;
  }
  if (p.rough() && !(std::abs(p.tangential_restitution) == 1 && std::isinf(p.friction))) lossless = false;
  const std::string what =
      names.gravity + " along periodic axis " + "xyz"[axis] + " (" + format_number(p.gravity[std::size_t(axis)]) + ")";
  if (!frictional_wall)
    return what +
           " with no frictional wall: nothing takes momentum along that axis from the spheres (collisions between "
           "them conserve it, smooth walls push along their normals only), so their speeds grow without bound and "
           "the run reaches no steady state; for a chute give the walls friction (rough spheres, a " +
           names.wall_tangential_restitution + " above -1 and a " + names.wall_friction + " above 0)";
  if (lossless)
    return what +
           " with every collision conserving energy: the spheres turn the potential energy they lose into speed "
           "without bound and the run reaches no steady state; give a " +
           names.restitution + " or " + names.wall_restitution + " below 1, or a finite friction";
  return "";
}

std::string collapse_advice(const Physics& p, const PhysicsNames& names) {
  if (p.elastic()) return "";
  // Name the inelastic law as given: the pairs', or the walls' when only those are inelastic.
  std::string law = names.restitution + " " + format_number(p.restitution);
  if (p.restitution == 1)
    for (int f = 0; f < 6; ++f)
      if (p.walls[std::size_t(f)].restitution != 1) {
        law = names.face_value(names.wall_restitution, f, p.walls[std::size_t(f)].restitution);
        break;
      }
  return "; with " + law +
         " it may also be an inelastic collapse (spheres settling onto each other, their collisions ever closer "
         "in time), which a longer " +
         names.contact_time + " lets through: give e.g. " + names.contact_time + " " +
         format_number(10 * p.contact_time) + " (now " + format_number(p.contact_time) +
         "; the TC model makes a sphere's collisions elastic within that time of its last one)";
}

}  // namespace hardsphere
