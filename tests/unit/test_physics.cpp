// The one physics configuration: validated() refuses what no engine can run, naming the value in
// the adapter's words, and reads gravity components at rounding level as zero.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "hardsphere/errors.hpp"
#include "hardsphere/physics.hpp"

using namespace hardsphere;

namespace {

std::string refusal(const Physics& p, const std::array<bool, 3>& periodic, const PhysicsNames& names = {}) {
  try {
    validated(p, periodic, names);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Physics, RefusesRestitutionAndContactTimesNoRunCouldEnd) {
  const std::array<bool, 3> walls{false, false, false};
  EXPECT_NE(refusal({0.0, 1e-4, {0, 0, 0}}, walls).find("restitution 0 must be in (0, 1]"), std::string::npos);
  EXPECT_NE(refusal({1.5, 1e-4, {0, 0, 0}}, walls).find("restitution 1.5"), std::string::npos);
  EXPECT_NE(refusal({std::nan(""), 1e-4, {0, 0, 0}}, walls).find("restitution nan"), std::string::npos);
  EXPECT_NE(refusal({0.9, -1, {0, 0, 0}}, walls).find("contact time -1 must be finite and >= 0"), std::string::npos);
  EXPECT_NE(refusal({0.9, 0, {0, 0, 0}}, walls).find("inelastic collapse"), std::string::npos);
  EXPECT_EQ(refusal({1.0, 0, {0, 0, 0}}, walls), "");  // elastic needs no contact time
  // Each adapter's names in the message: the command line's options.
  const PhysicsNames cli{"--restitution", "--contact-time", "--gravity", "walls on that axis (--boundary ...,w)"};
  EXPECT_NE(refusal({0.9, 0, {0, 0, 0}}, walls, cli).find("--contact-time 0 with --restitution 0.9"),
            std::string::npos);
}

// Gravity along periodic axes (a chute) is taken; one that cannot settle is said (unbounded_flow).
TEST(Physics, GravityAlongPeriodicAxesIsTakenAndRoundingIsZero) {
  const std::array<bool, 3> floor{true, true, false};
  EXPECT_EQ(refusal({1, 0, {0, 0.5, -1}}, floor), "");
  EXPECT_NE(refusal({1, 0, {0, 0, std::numeric_limits<double>::infinity()}}, floor).find("must be finite"),
            std::string::npos);
  // LAMMPS's 'spherical 0.0 -180.0' is -z with an x component of -1.2e-16: that is -z.
  const Physics down = validated({1, 0, {-1.2246467991473532e-16, 0, -1}}, floor);
  EXPECT_EQ(down.gravity[0], 0.0);
  EXPECT_EQ(down.gravity[2], -1.0);
  // Huge magnitudes do not overflow the comparison; a real tilt is kept.
  EXPECT_EQ(validated({1, 0, {1e-290, 0, -1e300}}, floor).gravity[0], 0.0);
  EXPECT_EQ(validated({1, 0, {1e-9, 0, -1}}, floor).gravity[0], 1e-9);
}

TEST(Physics, UnboundedFlowNamesWhyAChuteCannotSettle) {
  const std::array<bool, 3> floor{true, true, false}, none{true, true, true};
  Physics p;
  p.gravity = {0.5, 0, -1};
  // Smooth walls take no momentum along x, whatever the restitution.
  const std::string smooth = unbounded_flow(p, floor);
  EXPECT_NE(smooth.find("gravity along periodic axis x (0.5) with no frictional wall"), std::string::npos) << smooth;
  p.restitution = 0.5, p.contact_time = 1e-4;
  EXPECT_NE(unbounded_flow(p, floor).find("no frictional wall"), std::string::npos);
  // Rough spheres with friction: the floor brakes them, the inelastic pairs dissipate.
  p.tangential_restitution = 0.0, p.friction = 0.5;
  EXPECT_EQ(unbounded_flow(p, floor), "");
  EXPECT_NE(unbounded_flow(p, none).find("no frictional wall"), std::string::npos);  // no walls at all
  // A frictionless floor (mu_w 0) takes nothing either.
  Physics q = p;
  q.walls[4].friction = 0.0, q.walls[5].friction = 0.0;
  EXPECT_NE(unbounded_flow(q, floor).find("no frictional wall"), std::string::npos);
  // Perfectly rough, elastic, no sliding: nothing dissipates.
  Physics r;
  r.gravity = {0.5, 0, -1}, r.tangential_restitution = 1.0;
  const std::string lossless = unbounded_flow(r, floor, {"--restitution"});
  EXPECT_NE(lossless.find("every collision conserving energy"), std::string::npos) << lossless;
  EXPECT_NE(lossless.find("give a --restitution"), std::string::npos) << lossless;
  // Gravity along wall axes only: nothing to say.
  Physics w;
  w.gravity = {0, 0, -1};
  EXPECT_EQ(unbounded_flow(w, floor), "");
}

// The option rules: a setting given where it has no effect is refused, one table for every face,
// each naming the setting in its own words (issue 42, item 14).
TEST(Physics, SettingsGivenWhereTheyHaveNoEffectAreRefused) {
  const std::array<bool, 3> floor{true, true, false};
  auto refused = [&](Physics p, PhysicsGiven given, const PhysicsNames& names = {}) {
    try {
      validated(p, floor, names, given);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  PhysicsGiven inertia, resting, contact, friction;
  inertia.inertia = resting.resting_time = contact.contact_time = friction.friction = true;
  Physics smooth;
  smooth.inertia = 0.5;
  EXPECT_EQ(refused(smooth, inertia),
            "inertia 0.5 has no effect: smooth spheres (tangential restitution -1) do not "
            "rotate; give a tangential restitution above -1");
  Physics rough = smooth;
  rough.tangential_restitution = 0.5;
  EXPECT_EQ(refused(rough, inertia), "");
  EXPECT_EQ(refused(smooth, {}), "");  // not given: the default, which nothing reads
  smooth.friction = std::numeric_limits<double>::infinity();
  EXPECT_NE(refused(smooth, friction).find("friction inf needs a tangential restitution above -1"), std::string::npos);
  Physics still;
  still.resting_time = 0.3;
  EXPECT_NE(refused(still, resting).find("resting time 0.3 has no effect without gravity"), std::string::npos);
  still.gravity = {0, 0, -1};
  EXPECT_EQ(refused(still, resting), "");
  Physics elastic;
  elastic.contact_time = 1e-3;
  const PhysicsNames lammps{"restitution", "contact_time"};
  EXPECT_NE(refused(elastic, contact, lammps).find("contact_time 0.001 has no effect with restitution 1"),
            std::string::npos);
  elastic.restitution = 0.5;
  EXPECT_EQ(refused(elastic, contact, lammps), "");
}

TEST(Physics, WallLawsAreRefusedOutsideTheirRangesNamingTheFace) {
  const std::array<bool, 3> floor_only{true, true, false}, walls{false, false, false};
  const auto refused = [](const Physics& p, const std::array<bool, 3>& periodic, const PhysicsGiven& given = {}) {
    try {
      validated(p, periodic, {}, given);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  Physics p;
  p.contact_time = 1e-4;
  p.walls[4].restitution = 0;
  EXPECT_NE(refused(p, floor_only).find("wall restitution zlo=0 must be in (0, 1]"), std::string::npos);
  p.walls[4].restitution = 0.5;
  EXPECT_EQ(refused(p, floor_only), "");
  p.contact_time = 0;  // an inelastic wall keeps the TC model's clock
  EXPECT_NE(refused(p, floor_only).find("contact time 0 with a wall restitution below 1"), std::string::npos);
  // A tangential law needs rough spheres; then its ranges, and a friction a sticking limit.
  Physics r;
  r.walls[1].friction = 0.3;
  EXPECT_NE(refused(r, walls).find("wall friction xhi=0.3 needs rough spheres"), std::string::npos);
  r.tangential_restitution = 0.5;
  EXPECT_EQ(refused(r, walls), "");
  r.walls[1].friction = -1;
  EXPECT_NE(refused(r, walls).find("wall friction xhi=-1 must be >= 0"), std::string::npos);
  r.walls[1].friction = 0.3;
  r.walls[1].tangential_restitution = -1;
  EXPECT_NE(refused(r, walls).find("wall friction xhi=0.3 needs a wall tangential restitution above -1"),
            std::string::npos);
  r.walls[1].tangential_restitution = 1.5;
  EXPECT_NE(refused(r, walls).find("wall tangential restitution xhi=1.5 must be in [-1, 1]"), std::string::npos);
  // A face named where the box has no wall is refused; a setting for every wall sets those that
  // exist, and is refused where there are none.
  Physics q;
  q.contact_time = 1e-4;
  for (WallLaw& w : q.walls) w.restitution = 0.5;
  PhysicsGiven all;
  all.all_walls = true;
  const Physics v = validated(q, floor_only, {}, all);
  EXPECT_EQ(v.walls[0].restitution, 1.0);
  EXPECT_EQ(v.walls[5].restitution, 0.5);
  EXPECT_NE(refused(q, {true, true, true}, all).find("the box has no walls"), std::string::npos);
  PhysicsGiven named;
  named.wall_faces[2] = true;
  EXPECT_NE(refused(q, floor_only, named).find("the box has no wall at ylo (axis y is periodic)"), std::string::npos);
}

TEST(Physics, WallSettingsReadOneValueOrFaceValueLists) {
  const auto refused = [](const std::string& text) {
    Physics p;
    PhysicsGiven g;
    try {
      parse_wall_setting(p, g, WallSetting::Restitution, text, "--wall-restitution");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  Physics p;
  PhysicsGiven g;
  parse_wall_setting(p, g, WallSetting::Restitution, "0.5", "--wall-restitution");
  EXPECT_TRUE(g.all_walls);
  for (const WallLaw& w : p.walls) EXPECT_EQ(w.restitution, 0.5);
  Physics q;
  PhysicsGiven h;
  parse_wall_setting(q, h, WallSetting::Friction, "zlo=0.3,xhi=inf", "--wall-friction");
  EXPECT_FALSE(h.all_walls);
  EXPECT_EQ(*q.walls[4].friction, 0.3);
  EXPECT_EQ(*q.walls[1].friction, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(q.walls[0].friction);
  EXPECT_TRUE(h.wall_faces[4] && h.wall_faces[1] && !h.wall_faces[0]);
  EXPECT_NE(refused("abc").find("--wall-restitution 'abc': 'abc' is not a number"), std::string::npos);
  EXPECT_NE(refused("zlo=0.5,top=1").find("unknown face 'top'"), std::string::npos);
  EXPECT_NE(refused("zlo=0.5,zlo=0.7").find("names face zlo twice"), std::string::npos);
  EXPECT_NE(refused("zlo=0.5,0.7").find("'0.7' is not face=value"), std::string::npos);
  EXPECT_NE(refused("zlo=").find("'' is not a number"), std::string::npos);
  EXPECT_NE(refused("=0.5").find("names no face"), std::string::npos);
  EXPECT_NE(refused("zlo=0.5,").find("'' is not face=value"), std::string::npos);
}
