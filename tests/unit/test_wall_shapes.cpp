// Shaped walls (Physics::shapes, wall_shapes.hpp) in the stepper against analytic results: a
// bounce off a tilted plane under gravity is the reflection about n with e; a sphere inside a
// cylinder keeps its speed and its angular momentum about the axis, stays inside and meets the
// wall once per analytic chord; a fast graze of a sphere obstacle within one step is caught at
// its analytic contact; a fast drum holds a sliding sphere at tan theta = mu and one released at
// the bottom is carried up past that angle and slides back; the drum's work closes the energy
// budget; a turning plate carries a sphere round and its work closes the budget too. Parsing
// and refusals: the end of this file.
#include <gtest/gtest.h>

#include <cmath>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/stepper.hpp"
#include "hardsphere/wall_shapes.hpp"

using namespace hardsphere;

namespace {

//! One sphere (radius 0.5, mass 1) in a 20^3 box walled along the non-periodic axes.
ParticleSystem one_sphere(Vec3d pos, Vec3d vel, std::array<bool, 3> periodic = {false, false, false}) {
  ParticleSystem s;
  s.box = Box::from_lengths({20, 20, 20}, periodic);
  s.push_back(1, 1, 0.5, 1.0, pos, vel, {0, 0, 0}, {0, 0, 0});
  return s;
}

WallShape wall(const std::string& spec) { return parse_wall_shape(spec, "wall '" + spec + "'"); }

}  // namespace

TEST(WallShapes, BounceOffATiltedPlaneUnderGravityIsTheReflectionWithE) {
  // Plane through (10, 10, 5) tilted by 0.3 about y; a sphere dropped from rest falls straight
  // down, meets it after t_c (its normal gap s0 closing at g cos(theta) t^2 / 2) at v_c = -g t_c z,
  // and leaves at v_c - (1 + e)(v_c . n) n; a quarter of t_c later it has gained g t_c / 4.
  const double th = 0.3, e = 0.5, g = 1.0, dt = 1e-3;
  const Vec3d n{std::sin(th), 0, std::cos(th)}, p{10, 10, 5}, x0{10, 10, 8};
  Physics ph;
  ph.gravity = {0, 0, -g};
  ph.contact_time = kDefaultContactTime;
  WallShape w = wall("plane 10 10 5 " + std::to_string(n.x) + " 0 " + std::to_string(n.z) + " restitution 0.5");
  w.normal = n;  // exactly
  ph.shapes = {w};
  StepperConfig cfg;
  cfg.dt = dt;
  auto st = make_stepper(one_sphere(x0, {}), ph, cfg);
  const double s0 = dot(x0 - p, n) - 0.5;
  const double tc = std::sqrt(2 * s0 / (g * n.z));
  const auto steps = std::int64_t(std::llround(1.25 * tc / dt));
  st->run(steps);
  ASSERT_EQ(st->counters().wall_collisions, 1);
  const Vec3d vc{0, 0, -g * tc};
  const Vec3d v1 = vc - (1 + e) * dot(vc, n) * n;
  const double t_after = double(steps) * dt - tc;
  const Vec3d v = st->state().vel[0];
  EXPECT_NEAR(v.x, v1.x, 1e-12);
  EXPECT_NEAR(v.y, v1.y, 1e-12);
  EXPECT_NEAR(v.z, v1.z - g * t_after, 1e-12);
  const Vec3d xc = x0 + Vec3d{0, 0, -0.5 * g * tc * tc};
  const Vec3d x = st->state().pos[0];
  EXPECT_NEAR(x.x, xc.x + v1.x * t_after, 1e-12);
  EXPECT_NEAR(x.z, xc.z + v1.z * t_after - 0.5 * g * t_after * t_after, 1e-12);
}

TEST(WallShapes, SphereInsideACylinderKeepsSpeedStaysInsideAndBouncesOncePerChord) {
  // Axis z through (10, 10), R = 5: the centre moves on chords of the circle of radius 4.5, each
  // 2 sqrt(4.5^2 - b^2) long for the impact parameter b, which reflections keep (as they keep
  // L_z about the axis).
  const Vec3d x0{10, 9, 3}, v0{1, 0.3, 0.7};
  Physics ph;
  ph.shapes = {wall("cylinder z 10 10 5 inside")};
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(one_sphere(x0, v0, {false, false, true}), ph, cfg);
  const double vp = std::hypot(v0.x, v0.y), D = 4.5;
  const double b = std::abs(-1.0 * v0.x) / vp;  // |rho0 x v| / |v|, rho0 = (0, -1)
  const double along = (0 * v0.x + -1.0 * v0.y) / vp;
  const double t1 = (-along + std::sqrt(along * along - (1 - D * D))) / vp;  // first contact
  const double chord = 2 * std::sqrt(D * D - b * b) / vp;
  const double speed0 = std::sqrt(dot(v0, v0)), lz0 = (x0.x - 10) * v0.y - (x0.y - 10) * v0.x;
  for (int k = 0; k < 5000; ++k) {  // t = 50
    st->run(1);
    const ParticleSystem s = st->state();
    const double rho = std::hypot(s.pos[0].x - 10, s.pos[0].y - 10);
    ASSERT_LE(rho, D + 1e-12) << "outside the cylinder at step " << k;
    ASSERT_NEAR(std::sqrt(dot(s.vel[0], s.vel[0])), speed0, 1e-12);
    ASSERT_NEAR((s.pos[0].x - 10) * s.vel[0].y - (s.pos[0].y - 10) * s.vel[0].x, lz0, 1e-11);
    const double t = 0.01 * (k + 1);
    const double expected = t < t1 ? 0 : std::floor((t - t1) / chord) + 1;
    const double frac = t < t1 ? 1 : std::fmod(t - t1, chord);
    if (frac > 1e-9 && chord - frac > 1e-9) ASSERT_EQ(double(st->counters().wall_collisions), expected) << "t " << t;
  }
  EXPECT_GE(st->counters().wall_collisions, 5);
}

TEST(WallShapes, AGrazeOfASphereObstacleWithinOneStepIsCaught) {
  // A sphere at 400 passes a sphere obstacle (centre (10, 10, 10), R 1) at impact parameter 1.2 <
  // 1.5: it is clear at both ends of the 0.01 step (4 long) and overlaps in between. Contact at
  // x = 10 - 0.9, normal (-0.6, 0.8, 0): it leaves at (112, 384, 0).
  Physics ph;
  ph.shapes = {wall("sphere 10 10 10 1 outside")};
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(one_sphere({8, 11.2, 10}, {400, 0, 0}), ph, cfg);
  st->run(1);
  const ParticleSystem s = st->state();
  EXPECT_EQ(st->counters().wall_collisions, 1);
  EXPECT_NEAR(s.vel[0].x, 112, 1e-10);
  EXPECT_NEAR(s.vel[0].y, 384, 1e-10);
  const double t_after = 0.01 - 1.1 / 400;
  EXPECT_NEAR(s.pos[0].x, 9.1 + 112 * t_after, 1e-10);
  EXPECT_NEAR(s.pos[0].y, 11.2 + 384 * t_after, 1e-10);
}

namespace {

//! A drum: cylinder along y through (10, 10) (x, z), R = 5, turning at omega about +y (its bottom
//! moves towards -x), wall friction mu, under gravity -z; a rough sphere resting on it at angle th
//! from the bottom towards -x (tan th = mu: kinetic friction mu N holds it against g sin th).
struct Drum {
  double omega, mu, th;
  Physics physics() const {
    Physics ph;
    ph.gravity = {0, 0, -1};
    ph.tangential_restitution = 0;
    ph.shapes = {wall("cylinder y 10 10 5 rotate " + std::to_string(omega) + " tangential_restitution 0 friction " +
                      std::to_string(mu))};
    return ph;
  }
  ParticleSystem sphere() const { return one_sphere({10 - 4.5 * std::sin(th), 10, 10 - 4.5 * std::cos(th)}, {}); }
  static double angle(const ParticleSystem& s) { return std::atan2(10 - s.pos[0].x, 10 - s.pos[0].z); }
};

double energy(const ParticleSystem& s, double q) {
  const Vec3d v = s.vel[0], w = s.omega[0];
  return 0.5 * dot(v, v) + 0.5 * q * 0.25 * dot(w, w) + s.pos[0].z;
}

//! Runs 20000 steps of 1e-3 and checks the walls' energy budget: their work (at least 0.1) is
//! the energy change plus what the wall contacts took, to rounding. Returns the counters.
StepCounters run_checking_wall_budget(const ParticleSystem& sys, const Physics& ph) {
  StepperConfig cfg;
  cfg.dt = 1e-3;
  auto st = make_stepper(sys, ph, cfg);
  const double e0 = energy(st->state(), 0.4);
  st->run(20000);
  const StepCounters c = st->counters();
  const double e1 = energy(st->state(), 0.4);
  const double taken = c.wall_dissipated_normal + c.wall_dissipated_tangential;
  EXPECT_GT(std::abs(c.wall_work), 0.1);
  EXPECT_NEAR(c.wall_work, e1 - e0 + taken, 1e-9 * (std::abs(c.wall_work) + taken));
  return c;
}

}  // namespace

TEST(WallShapes, ADrumHoldsASlidingSphereWhereTanThetaIsMu) {
  // The drum's surface (100) outruns the sphere: it slides, friction mu N up the wall against
  // g sin(theta) down it, balanced at tan(theta) = mu (stable: above, gravity wins). Each step's
  // resting contact takes the normal impulse |g_n| dt and a tangential mu |g_n| dt, so the
  // balance holds per step; the sphere's spin-up to rolling takes q V / (mu g cos th) ~ 90, far
  // beyond t = 5. Measured: the sphere put there stays at atan(mu) to the last bit (deviation 0);
  // one put 0.02 above slides back past it and swings about it, never beyond its mirror angle.
  const double mu = 0.5, eq = std::atan(mu);
  StepperConfig cfg;
  cfg.dt = 1e-3;
  for (const double start : {eq, eq + 0.02}) {
    const Drum d{20, mu, start};
    auto st = make_stepper(d.sphere(), d.physics(), cfg);
    double low = start, high = start;
    for (int k = 0; k < 5000; ++k) {
      st->run(1);
      const double th = Drum::angle(st->state());
      low = std::min(low, th), high = std::max(high, th);
    }
    EXPECT_NEAR(high, start, 1e-12) << "start " << start;
    if (start == eq) {
      EXPECT_NEAR(low, eq, 1e-12);
    } else {  // measured: down to eq - 0.0157 (friction grows with the centripetal normal force)
      EXPECT_GT(low, 2 * eq - start - 1e-12);
      EXPECT_LT(low, eq - 0.01);
    }
    EXPECT_GT(st->counters().resting_contacts, 4000);
  }
}

TEST(WallShapes, ADrumCarriesASphereUpPastTanThetaMuAndItSlidesBack) {
  // Released at rest at the bottom of the fast drum, the sphere is dragged up by mu N, passes
  // tan(theta) = mu (where gravity balances friction) and turns back: it swings about that
  // angle (small angles: between 0 and twice it), sliding back after each rise.
  const double mu = 0.3, eq = std::atan(mu);
  const Drum d{20, mu, 0};
  StepperConfig cfg;
  cfg.dt = 1e-3;
  auto st = make_stepper(d.sphere(), d.physics(), cfg);
  double top = 0, after_top = 1e9;
  for (int k = 0; k < 10000; ++k) {  // a swing: 2 pi sqrt(4.5 / g) ~ 13.3
    st->run(1);
    const double th = Drum::angle(st->state());
    if (th > top) top = th, after_top = th;
    after_top = std::min(after_top, th);
  }
  EXPECT_GT(top, 1.8 * eq);
  EXPECT_LT(top, 2.2 * eq);
  EXPECT_LT(after_top, top - 0.5 * eq) << "it slid back";
}

TEST(WallShapes, TheDrumsWorkClosesTheEnergyBudget) {
  // Work of the wall = energy change + what the contacts took, to rounding: a sphere released
  // at 0.2 rad on a slow drum (it rolls and slips) over 20000 steps.
  const Drum d{0.7, 0.4, 0.2};
  Physics ph = d.physics();
  ph.shapes[0].law.restitution = 0.7;
  ph.contact_time = kDefaultContactTime;
  const StepCounters c = run_checking_wall_budget(d.sphere(), ph);
  ASSERT_EQ(c.shapes.size(), 1u);
  EXPECT_GT(c.shapes[0].resting_contacts + c.shapes[0].collisions, 1000);
  EXPECT_EQ(c.wall_work, c.shapes[0].work);
}

namespace {

//! A turning plate: the plane z = 2 turning at omega about +z through (10, 10), wall friction
//! mu, under gravity -z; a rough sphere resting on it at rest at (13, 10), 3 from the axis.
Physics plate(double omega, double mu, double e = 1) {
  Physics ph;
  ph.gravity = {0, 0, -1};
  ph.tangential_restitution = 0;
  ph.contact_time = kDefaultContactTime;
  ph.shapes = {wall("plane 10 10 2 0 0 1 rotate " + std::to_string(omega) + " restitution " + std::to_string(e) +
                    " tangential_restitution 0 friction " + std::to_string(mu))};
  return ph;
}

}  // namespace

TEST(WallShapes, ATurningPlateCarriesASphereRound) {
  // The plate's surface under the sphere moves at omega r = 6 along +y; the sphere slides, and
  // each step's resting contact gives it mu |g| dt along the surface's velocity (as the drum's
  // wall): v_y grows by mu g dt a step (measured: to 2e-17). Over 2000 steps friction carries it
  // round the axis (its angular momentum about the axis grows, positive) and it stays on the
  // plate (centre at z = 2.5 to rounding).
  StepperConfig cfg;
  cfg.dt = 1e-3;
  auto st = make_stepper(one_sphere({13, 10, 2.5}, {}), plate(2, 0.5), cfg);
  st->run(2);  // the first step ends just inside the plate; the second starts the resting contact
  for (int k = 0; k < 4; ++k) {
    const double vy = st->state().vel[0].y;
    st->run(1);
    EXPECT_NEAR(st->state().vel[0].y - vy, 0.5 * 1e-3, 1e-14) << "step " << k + 3;
  }
  double lz_prev = 0;
  for (int k = 0; k < 20; ++k) {
    st->run(100);
    const ParticleSystem s = st->state();
    const double lz = (s.pos[0].x - 10) * s.vel[0].y - (s.pos[0].y - 10) * s.vel[0].x;
    EXPECT_GT(lz, lz_prev) << "step " << 100 * (k + 1);
    EXPECT_NEAR(s.pos[0].z, 2.5, 1e-12);
    lz_prev = lz;
  }
  EXPECT_GT(std::atan2(st->state().pos[0].y - 10, st->state().pos[0].x - 13 + 3), 0.0);
  EXPECT_GT(st->counters().resting_contacts, 1900);
}

TEST(WallShapes, ARotationSetBetweenStepsIsTheWallBuiltTurning) {
  // set_shape_rotation (a LAMMPS region's rotate v_theta, its rate per step): a plate built at
  // rest and set turning before the first step runs the same steps, bit for bit, as the plate
  // built turning; set back to 0 it stops carrying the sphere's surface along.
  StepperConfig cfg;
  cfg.dt = 1e-3;
  auto built = make_stepper(one_sphere({13, 10, 2.5}, {}), plate(2, 0.5), cfg);
  auto set = make_stepper(one_sphere({13, 10, 2.5}, {}), plate(0, 0.5), cfg);
  set->set_shape_rotation(0, 2);
  built->run(500);
  set->run(500);
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(built->state().pos[0][d], set->state().pos[0][d]);
    EXPECT_EQ(built->state().vel[0][d], set->state().vel[0][d]);
  }
  EXPECT_EQ(built->counters().wall_work, set->counters().wall_work);
  EXPECT_THROW(set->set_shape_rotation(0, std::nan("")), InputError);
  EXPECT_THROW(set->set_shape_rotation(1, 1), std::out_of_range);
}

TEST(WallShapes, ATurningPlatesWorkClosesTheEnergyBudget) {
  // Work of the plate = energy change + what the contacts took, to rounding: a sphere dropped
  // from 0.3 above a slow inelastic plate (it bounces, then rests, slips and rolls).
  const StepCounters c = run_checking_wall_budget(one_sphere({13, 10, 2.8}, {}), plate(0.7, 0.4, 0.7));
  ASSERT_EQ(c.shapes.size(), 1u);
  EXPECT_GT(c.shapes[0].collisions, 3);
  EXPECT_GT(c.shapes[0].resting_contacts, 1000);
}

TEST(WallShapes, ParsingNamesTheWallAndTheWord) {
  const WallShape w = wall("cone z 10 10 2 8 1 4 restitution 0.5");
  EXPECT_EQ(w.kind, ShapeKind::Cone);
  EXPECT_EQ(w.point.x, 10);
  EXPECT_EQ(w.radius_hi, 4);
  EXPECT_EQ(describe(w), "cone z 10 10 2 8 1 4 restitution 0.5");
  EXPECT_EQ(describe(wall("cylinder x 3 4 2 outside bounds 1 5 rotate 0.5")),
            "cylinder x 3 4 2 outside bounds 1 5 rotate 0.5 restitution 1");
  for (const char* bad : {"", "box 1 2 3", "plane 1 2 3 0 0", "plane 1 2 3 0 0 x", "cylinder w 1 1 1",
                          "sphere 1 1 1 1 bounds 0 1", "plane 0 0 0 0 0 1 axis z", "sphere 1 1 1 1 inside inside",
                          "cylinder z 1 1 1 shear 1 0 0", "sphere 1 1 1 1 sticky"})
    EXPECT_THROW(wall(bad), InputError) << bad;
  try {
    wall("cylinder z 1 1 1 frobnicate");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wall 'cylinder z 1 1 1 frobnicate': unknown keyword 'frobnicate'"),
              std::string::npos)
        << e.what();
  }
}

TEST(WallShapes, RefusesBadValuesNamingThem) {
  const std::array<bool, 3> walls{false, false, false};
  const auto refused = [&](const std::string& spec, const std::string& says, std::array<bool, 3> periodic) {
    try {
      validated_shape(wall(spec), periodic);
      ADD_FAILURE() << spec << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  refused("plane 1 1 1 0 0 0", "normal 0 0 0 has no direction", walls);
  refused("sphere 1 1 1 0", "radius 0 must be > 0", walls);
  refused("cylinder z 1 1 -2", "radius -2 must be > 0", walls);
  refused("cylinder z 1 1 2 bounds 3 1", "bounds 3 1 must have LO < HI", walls);
  refused("cone z 1 1 2 1 1 3", "axial extent 2 1 must have LO < HI", walls);
  refused("cone z 1 1 1 2 0 0", "radii 0 0 must be >= 0 and not both 0", walls);
  refused("plane 0 0 0 0 0 1 shear 0 0 1", "has a part 1 along the normal", walls);
  refused("plane 0 0 0 0 0 1", "periodic axis z", {true, true, true});
  refused("cylinder x 1 1 2", "periodic axis z crosses the cylinder", {false, false, true});
  refused("plane 0 0 0 0 0 1 rotate 1", "periodic axis x runs along the rotating plane", {true, false, false});
  refused("sphere 1 1 1 nan", "radius nan must be finite", walls);
  // The law: through validated(), as every face reaches it.
  Physics p;
  p.shapes = {wall("sphere 1 1 1 1 restitution 1.5")};
  EXPECT_THROW(validated(p, walls), InputError);
  p.shapes = {wall("sphere 1 1 1 1 friction 0.5")};
  EXPECT_THROW(validated(p, walls), InputError);  // smooth spheres
  // A sphere that starts overlapping a wall; the event engine's refusal names the stepper.
  Physics q;
  q.shapes = {wall("sphere 10 10 10 2 outside")};
  try {
    make_stepper(one_sphere({11, 10, 10}, {}), q, {});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("overlaps wall 'sphere 10 10 10 2 outside' by 1.5"), std::string::npos)
        << e.what();
  }
  try {
    EventEngine ev(one_sphere({15, 10, 10}, {}), q, {});
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shaped walls run in the stepper only"), std::string::npos) << e.what();
  }
}
