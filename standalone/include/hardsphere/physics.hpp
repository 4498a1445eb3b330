#pragma once
//! The collision law and the external field of a scene: one configuration that both engines, the
//! command line and the LAMMPS fix take, checked in one place (validated()).
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "hardsphere/wall_shapes.hpp"

namespace hardsphere {

//! TC-model contact time the adapters use when the restitution is below 1 and none is given:
//! short against a mean free time (~0.1-10 in reduced units for phi 0.45-0.01).
constexpr double kDefaultContactTime = 1e-4;

//! A gravity component below this fraction of the largest is rounding (LAMMPS's `spherical` angles give
//! ~1e-16) and counts as zero.
constexpr double kGravityRounding = 1e-12;

//! The event engine's resting time when none is given, as a fraction of the time a sphere of the
//! smallest diameter d takes to fall d from rest, sqrt(d / |g|): hops of 1e-5 d (the stepper
//! takes its sub-step).
constexpr double kRestingTimeFraction = 0.01;

//! The box faces in the order Physics::walls holds them (face 2 d + 1 is axis d's upper wall),
//! named as every face names them.
constexpr std::array<const char*, 6> kFaceNames{"xlo", "xhi", "ylo", "yhi", "zlo", "zhi"};

struct Physics {
  //! Normal restitution of sphere-sphere collisions, in (0, 1] (the walls': `walls`).
  double restitution = 1.0;
  //! TC model of inelastic collapse (Luding and McNamara 1998): a collision within this time of
  //! either sphere's previous collision is elastic, so no finite time holds infinitely many.
  //! Must be > 0 when the restitution is below 1.
  double contact_time = 0.0;
  //! Uniform acceleration, along any axis: flights are parabolas, relative motion of pairs stays
  //! straight. Potential energy -m g.(x - lo), with x unwrapped (pos + image L) along periodic
  //! axes (a chute: gravity along a periodic axis; unbounded_flow() says when it cannot settle).
  std::array<double, 3> gravity{0, 0, 0};
  //! Resting contacts under gravity: a wall contact slower than |g_d| resting_time along an axis
  //! whose gravity pulls into that wall does not bounce but rests (a sphere at rest on a floor
  //! would bounce at once again, without end): it leaves at half the speed gravity builds over
  //! the resting time (the stepper: the rest of its sub-step), so it is back on the wall after
  //! it. 0: the stepper's sub-step, the event engine's kRestingTimeFraction sqrt(d / |g|).
  double resting_time = 0;
  //! Rough spheres: tangential restitution beta in [-1, 1] of the contact points' relative
  //! velocity (-1: smooth, no rotation; +1: perfectly rough). Walls take it as pairs do.
  double tangential_restitution = -1.0;
  //! Walton's Coulomb friction mu >= 0: a tangential impulse above mu times the normal one slides
  //! at that limit (beta is then the sticking limit beta0). Infinity: constant beta.
  double friction = std::numeric_limits<double>::infinity();
  //! Moment of inertia I = q m r^2 (r the radius) of every sphere, q in (0, 2/3] (2/5: solid).
  double inertia = 0.4;

  //! Each box face's law (kFaceNames order); the default is elastic and, for smooth spheres,
  //! frictionless. A wall collision with e_w < 1 takes the TC model as pairs do.
  std::array<WallLaw, 6> walls{};
  //! Shaped walls (wall_shapes.hpp): planes, cylinders, spheres, cones, each with its own law;
  //! the stepper only. Empty: the box faces alone.
  std::vector<WallShape> shapes;

  //! Every collision elastic: pairs and walls (the TC model's clock is kept otherwise).
  bool elastic() const { return restitution == 1.0 && !inelastic_walls(); }
  bool inelastic_walls() const {
    for (const WallLaw& w : walls)
      if (w.restitution != 1.0) return true;
    for (const WallShape& w : shapes)
      if (w.law.restitution != 1.0) return true;
    return false;
  }
  //! Some face's law differs from the default (the run summary then reports the walls' laws).
  bool wall_laws() const { return walls != std::array<WallLaw, 6>{}; }
  //! Face f's tangential restitution and friction, the spheres' where the face gives none.
  double wall_tangential_restitution(int f) const {
    return walls[std::size_t(f)].tangential_restitution.value_or(tangential_restitution);
  }
  double wall_friction(int f) const { return walls[std::size_t(f)].friction.value_or(friction); }
  bool rough() const { return tangential_restitution != -1.0; }
  bool has_gravity() const { return gravity != std::array<double, 3>{0, 0, 0}; }
};

//! `g` with its components at rounding level (below kGravityRounding of the largest) set to zero.
std::array<double, 3> without_rounding(std::array<double, 3> g);

//! How an adapter names the settings in messages: the command line's options, the fix's keywords.
struct PhysicsNames {
  std::string restitution = "restitution";
  std::string contact_time = "contact time";
  std::string gravity = "gravity";
  std::string walls = "walls on that axis";  //!< how the face puts walls on an axis (no message uses it now)
  std::string resting_time = "resting time";
  std::string tangential_restitution = "tangential restitution";
  std::string friction = "friction";
  std::string inertia = "inertia";
  std::string wall_restitution = "wall restitution";
  std::string wall_tangential_restitution = "wall tangential restitution";
  std::string wall_friction = "wall friction";
  //! How a face's value is named: `wall_restitution zlo=0.5` on the command line.
  std::string face_value(const std::string& name, int face, double value) const;
  std::string face_separator = "=";
};

//! Which settings the user gave (each adapter knows its own options or keywords). A setting given
//! where it has no effect is refused, by the same rules on every face (the option rules in
//! validated()): a contact time with a restitution of 1 (elastic collisions), a resting time
//! without gravity, a friction or an inertia for smooth spheres (tangential restitution -1).
struct PhysicsGiven {
  bool contact_time = false;
  bool resting_time = false;
  bool friction = false;
  bool inertia = false;
  //! Wall laws: the faces a wall setting named (refused where the box has no wall), and whether
  //! one was given for every wall at once (refused where the box has none; it sets the faces with
  //! walls only).
  std::array<bool, 6> wall_faces{};
  bool all_walls = false;
};

//! `p` checked against boxes with these periodic axes, with gravity components at rounding level
//! (kGravityRounding) set to zero. Throws InputError naming the value: a restitution outside
//! (0, 1], a contact time that is negative, not finite or 0 with a restitution below 1, a gravity
//! that is not finite, a tangential restitution outside
//! [-1, 1], a friction below 0 or NaN, or finite without a tangential restitution above -1, an
//! inertia outside (0, 2/3], a wall law's value outside these ranges, or a wall tangential law for
//! smooth spheres (a frictional wall turns spheres: they need spins, which only rough scenes
//! carry); then a setting in `given` that would have no effect (PhysicsGiven). The laws of periodic
//! faces are reset to the default (a setting for every wall sets the faces that have walls).
Physics validated(Physics p, const std::array<bool, 3>& periodic, const PhysicsNames& names = {},
                  const PhysicsGiven& given = {});

//! A gravity as validated() takes it (also for a change on a live engine): every component
//! finite (InputError naming it otherwise), those at rounding level set to zero.
std::array<double, 3> validated_gravity(const std::array<double, 3>& g, const PhysicsNames& names = {});

//! The wall laws' settings, as every face names them (PhysicsNames::wall_*).
enum class WallSetting { Restitution, TangentialRestitution, Friction };

//! Sets `setting` of box face `face` (a kFaceNames entry; "" : every face) to `value`, recording
//! it in `given` (validated() then refuses a face without a wall, and a setting for every wall in
//! a box without any). Throws InputError naming `option` for an unknown face.
void set_wall_law(Physics& p, PhysicsGiven& given, WallSetting setting, const std::string& face, double value,
                  const std::string& option);

//! The command line's and Python's text form of a wall setting: one number for every wall
//! ("0.5") or a list of face=value ("zlo=0.5,zhi=0.9"), applied with set_wall_law(). Throws
//! InputError naming `option` and the text for anything else (a number that is not one, an
//! unknown face, a face twice, an empty item).
void parse_wall_setting(Physics& p, PhysicsGiven& given, WallSetting setting, const std::string& text,
                        const std::string& option);

//! Why a scene with gravity along a periodic axis reaches no steady state (empty when it can or
//! has no such gravity): no wall takes tangential impulse (pair collisions conserve momentum,
//! smooth walls push along their normals only), or no collision dissipates energy. The adapters
//! run such a scene and warn with this text.
std::string unbounded_flow(const Physics& p, const std::array<bool, 3>& periodic, const PhysicsNames& names = {});

//! What a refusal of jammed spheres adds for inelastic collisions (empty when elastic): the
//! chain may be an inelastic collapse (a settling bed), which a longer contact time lets
//! through, named as the face names it.
std::string collapse_advice(const Physics& p, const PhysicsNames& names);

}  // namespace hardsphere
