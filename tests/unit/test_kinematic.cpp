// Kinematic spheres (ParticleSystem::kinematic): infinite mass, prescribed straight motion. A free
// sphere takes the whole impulse (kernel::collide_kinematic()): it rebounds off a frozen sphere at
// -e v_n, off a moving one at v - (1 + e) ((v - u).n) n, rough spheres take Walton's tangential law
// with the kinematic surface's velocity; under gravity a sphere on a frozen base rests; a bed on a
// frozen base stays above it and the energy budget closes with the work the kinematic spheres do.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/stepper.hpp"

using namespace hardsphere;

namespace {

//! Sphere 1 free (radius 0.5, mass 1) at `p` with `v`; sphere 2 kinematic at the centre of a
//! periodic 10^3 box (or one with z walls) with `u`.
ParticleSystem pair_with_kinematic(Vec3d p, Vec3d v, Vec3d u, bool z_walls = false) {
  ParticleSystem s;
  s.box = Box::from_lengths({10, 10, 10}, {true, true, !z_walls});
  s.push_back(1, 1, 0.5, 1.0, p, v);
  s.push_back(2, 2, 0.5, 3.0, {5, 5, 5}, u);
  s.kinematic = {0, 1};
  return s;
}

std::unique_ptr<StepperBase> stepper(const ParticleSystem& s, const Physics& p, Precision prec = Precision::Double,
                                     double dt = 0.01) {
  StepperConfig cfg;
  cfg.dt = dt;
  return make_stepper(s, p, cfg, prec);
}

Physics restituted(double e) {
  Physics p;
  p.restitution = e;
  p.contact_time = kDefaultContactTime;
  return p;
}

}  // namespace

TEST(Kinematic, HeadOnReboundOffAFrozenSphereIsMinusEVn) {
  for (const Precision prec : {Precision::Double, Precision::Float})
    for (const double e : {1.0, 0.5}) {
      // 0.5 apart along x at speed 1: contact at t = 0.5, then it leaves at e.
      auto st = stepper(pair_with_kinematic({6.5, 5, 5}, {-1, 0, 0}, {}), restituted(e), prec);
      st->run(100);
      const ParticleSystem end = st->state();
      const double tol = prec == Precision::Float ? 1e-5 : 1e-13;
      EXPECT_NEAR(end.vel[0].x, e, tol);
      EXPECT_NEAR(
          end.pos[0].x, 6.0 + e * 0.5,
          prec == Precision::Float ? 1e-4 : 1e-13);  // float: 100 drifts  // contact at x = 6, then 0.5 of flight
      EXPECT_EQ(end.pos[1].x, 5.0);                  // the frozen sphere never moves
      EXPECT_EQ(end.vel[1].x, 0.0);
      EXPECT_EQ(st->counters().kinematic_collisions, 1);
      EXPECT_EQ(st->counters().collisions, 0);
      EXPECT_NEAR(st->counters().wall_dissipated_normal, 0.5 * (1 - e * e), tol);
      EXPECT_EQ(st->counters().kinematic_work, 0.0);
    }
}

TEST(Kinematic, MovingKinematicSphereGivesVMinusOnePlusETimesRelativeNormal) {
  // Oblique: the free sphere's velocity after is v - (1 + e) ((v - u).n) n, n along the centre
  // line at contact; the work the kinematic sphere did is m dv . u.
  const double e = 0.7;
  const Vec3d v{-1, 0.3, 0}, u{0.4, 0.1, 0};
  const ParticleSystem s = pair_with_kinematic({6.5, 5.3, 5}, v, u);
  auto st = stepper(s, restituted(e));
  st->run(200);
  ASSERT_EQ(st->counters().kinematic_collisions, 1);
  // Contact: |(1.5, 0.3) + t (v - u)| = 1 with v - u = (-1.4, 0.2, 0).
  const Vec3d dr0{1.5, 0.3, 0}, w = v - u;
  const double a = dot(w, w), b = dot(dr0, w), c = dot(dr0, dr0) - 1;
  const double t = (-b - std::sqrt(b * b - a * c)) / a;
  const Vec3d n = dr0 + t * w;  // |n| = 1 at contact
  const Vec3d expect = v - (1 + e) * dot(w, n) * n;
  const ParticleSystem end = st->state();
  EXPECT_NEAR(end.vel[0].x, expect.x, 1e-13);
  EXPECT_NEAR(end.vel[0].y, expect.y, 1e-13);
  EXPECT_NEAR(end.vel[1].x, u.x, 0);
  EXPECT_NEAR(end.pos[1].x, 5 + u.x * 2.0, 1e-13);  // on its line, 200 steps of 0.01
  const Vec3d dv = end.vel[0] - v;
  EXPECT_NEAR(st->counters().kinematic_work, dot(dv, u), 1e-13);
  // The budget: the free sphere's energy gain is the work less what the contact took.
  const double gain = 0.5 * (dot(end.vel[0], end.vel[0]) - dot(v, v));
  EXPECT_NEAR(gain, st->counters().kinematic_work - st->counters().wall_dissipated_normal, 1e-13);
}

TEST(Kinematic, RoughSphereTakesWaltonsTangentialLawOffAFrozenSphere) {
  // Head-on along x, spinning about z at 0.4: the contact point's velocity g = v - a w x n has a
  // tangential part -0.2 along y; the frozen sphere spins at 0.7 about z. Sticking (mu infinite): g_t leaves at -beta
  // g_t; sliding (mu = 0.02, below the sticking impulse (1 + beta) q / (1 + q) 0.2 = 0.074 over (1 + e) |v_n|): the
  // tangential velocity change is mu (1 + e) |v_n| against g_t.
  for (const double mu : {std::numeric_limits<double>::infinity(), 0.02})
    for (const Precision prec : {Precision::Double, Precision::Float}) {
      Physics p = restituted(0.8);
      p.tangential_restitution = 0.3;
      p.friction = mu;
      ParticleSystem s = pair_with_kinematic({6.5, 5, 5}, {-1, 0, 0}, {});
      s.omega = {{0, 0, 0.4}, {0, 0, 0.7}};
      auto st = stepper(s, p, prec);
      st->run(100);
      const ParticleSystem end = st->state();
      const double tol = prec == Precision::Float ? 2e-6 : 1e-13;
      EXPECT_NEAR(end.vel[0].x, 0.8, tol);
      const Vec3d n{1, 0, 0};  // from the frozen sphere to the free one; the contact point at -a n
      const Vec3d g = end.vel[0] - 0.5 * cross(end.omega[0], n);
      // The frozen sphere's spin 0.7 moves its surface at s = a_k w_k x n = 0.35 along y: the
      // relative tangential velocity before is -0.2 - 0.35.
      if (std::isinf(mu))
        EXPECT_NEAR(g.y - 0.35, 0.3 * 0.55, tol);
      else
        EXPECT_NEAR(end.vel[0].y, 0.02 * 1.8, tol);
      EXPECT_EQ(end.omega[1].z, prec == Precision::Float ? double(0.7f) : 0.7);  // its spin never changes
      EXPECT_NEAR(st->counters().kinematic_work, end.vel[0].y * 0.35, tol);      // m dv . s
    }
}

TEST(Kinematic, SphereOnThreeFrozenSpheresUnderGravityStaysAtRest) {
  // Three frozen unit spheres touching in a triangle, one free sphere placed at rest in their
  // pocket, touching all three. The resting rule along each centre line keeps it there: over 10^4
  // steps it moves by less than g dt^2 and its kinetic energy stays below the hop level (g dt)^2 / 2
  // (without the rule it would bounce for ever, and a lost contact let it sink through the base).
  ParticleSystem s;
  s.box = Box::from_lengths({10, 10, 10}, {true, true, false});
  const double r3 = std::sqrt(3.0), dt = 0.005;
  s.push_back(1, 1, 0.5, 1.0, {5, 5, 0.5}, {});
  s.push_back(2, 1, 0.5, 1.0, {6, 5, 0.5}, {});
  s.push_back(3, 1, 0.5, 1.0, {5.5, 5 + r3 / 2, 0.5}, {});
  const double rest_z = 0.5 + std::sqrt(1 - 1.0 / 3.0);  // 1/sqrt(3) across from each centre
  const Vec3d rest{5.5, 5 + r3 / 6, rest_z};
  s.push_back(4, 1, 0.5, 1.0, rest, {});
  s.kinematic = {1, 1, 1, 0};
  Physics p = restituted(0.5);
  p.gravity = {0, 0, -1};
  auto st = stepper(s, p, Precision::Double, dt);
  double ke_max = 0, moved = 0;
  for (int k = 0; k < 10000; ++k) {
    st->run(1);
    const ParticleSystem now = st->state();
    ke_max = std::max(ke_max, 0.5 * dot(now.vel[3], now.vel[3]));
    moved = std::max(moved, norm(now.pos[3] - rest));
  }
  EXPECT_LT(ke_max, 0.5 * dt * dt);
  EXPECT_LT(moved, dt * dt);
  EXPECT_GT(st->counters().resting_contacts, 10000);
  for (int b = 0; b < 3; ++b) EXPECT_EQ(st->state().pos[std::size_t(b)].z, 0.5);
}

TEST(Kinematic, BedOnAFrozenBaseStaysAboveItAndTheBudgetCloses) {
  // A 6 x 6 square lattice of frozen spheres (touching neighbours: allowed) at z = 0.5 under a
  // periodic x, y; 30 rough, inelastic free spheres fall on it and settle. No free sphere
  // overlaps the base beyond rounding, and the energy lost equals what the contacts took.
  ParticleSystem s;
  s.box = Box::from_lengths({6, 6, 12}, {true, true, false});
  std::int64_t id = 1;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) s.push_back(id++, 2, 0.5, 1.0, {0.5 + i, 0.5 + j, 0.5}, {});
  for (int k = 0; k < 30; ++k)
    s.push_back(id++, 1, 0.45, 0.9, {0.6 + (k % 5) * 1.2, 0.6 + (k / 5) % 5 * 1.2, 2.5 + 1.5 * (k / 25)},
                {0.3 * std::sin(k), 0.3 * std::cos(k), 0});
  s.kinematic.assign(s.size(), 0);
  for (std::size_t k = 0; k < 36; ++k) s.kinematic[k] = 1;
  Physics p = restituted(0.6);
  p.gravity = {0, 0, -1};
  p.contact_time = kDefaultContactTime;
  p.tangential_restitution = 0.4;
  p.friction = 0.5;
  auto energy = [&](const ParticleSystem& x) {
    double e = 0;
    for (std::size_t k = 36; k < x.size(); ++k)
      e += 0.5 * x.mass[k] * dot(x.vel[k], x.vel[k]) +
           0.5 * p.inertia * x.mass[k] * x.radius[k] * x.radius[k] * dot(x.omega[k], x.omega[k]) +
           x.mass[k] * x.pos[k].z;
    return e;
  };
  auto st = stepper(s, p, Precision::Double, 0.005);
  const double e0 = energy(st->state());
  // Measured: the deepest overlap with the base at any step's end is 1.8e-6, below g dt^2 = 2.5e-5
  // (resting contacts hop at that scale, as on a wall).
  const double tol = 1.0 * 0.005 * 0.005;
  for (int k = 0; k < 400; ++k) {
    st->run(10);
    const ParticleSystem now = st->state();
    for (std::size_t f = 36; f < now.size(); ++f) {
      ASSERT_GT(now.pos[f].z, 0.5 + 0.45 - tol) << "atom " << now.id[f] << " sank into the base";
      for (std::size_t b = 0; b < 36; ++b) {
        Vec3d d = now.pos[f] - now.pos[b];
        for (int a = 0; a < 2; ++a) d[a] -= 6 * std::nearbyint(d[a] / 6);
        ASSERT_GT(norm(d), 0.95 - tol) << "atom " << now.id[f] << " overlaps base atom " << now.id[b];
      }
    }
  }
  const StepCounters& c = st->counters();
  EXPECT_GT(c.kinematic_collisions, 30);
  EXPECT_GT(c.collisions, 10);
  EXPECT_EQ(c.kinematic_work, 0.0);  // a frozen base does no work
  EXPECT_NEAR(e0 - energy(st->state()), c.dissipated_normal + c.dissipated_tangential, 1e-10 * e0);
}

TEST(Kinematic, OverlappingKinematicSpheresAreAllowedAndNeverCollide) {
  ParticleSystem s = pair_with_kinematic({5.8, 5, 5}, {0, 0, 0}, {0, 0, 0});
  s.kinematic = {1, 1};
  s.vel[0] = {-0.1, 0, 0};
  auto st = stepper(s, Physics{});
  st->run(100);
  EXPECT_NEAR(st->state().pos[0].x, 5.7, 1e-13);  // on its line through the other
  EXPECT_EQ(st->counters().collisions + st->counters().kinematic_collisions, 0);
  validate_and_wrap(s, "test");  // two kinematic spheres may overlap
  s.kinematic = {0, 1};
  EXPECT_THROW(validate_and_wrap(s, "test"), InputError);  // a free sphere may not overlap one
}

TEST(Kinematic, RefusedWhereTheyCannotBeFollowed) {
  // The event engine does not follow them.
  const ParticleSystem s = pair_with_kinematic({7, 5, 5}, {}, {});
  try {
    EventEngine e(s, Physics{}, EventConfig{});
    FAIL() << "kinematic spheres accepted by the event engine";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stepper"), std::string::npos) << e.what();
  }
  // A kinematic sphere moving into a wall within the run: refused before the run.
  auto st = stepper(pair_with_kinematic({7, 5, 5}, {}, {0, 0, 1}, true), Physics{});
  st->run(100);  // at z = 6 after 1 time unit: 3.5 from the wall
  try {
    st->run(400);
    FAIL() << "a kinematic sphere crossing a wall was run";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("kinematic atom 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("along z"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(st->state().pos[1].z, 6.0, 1e-13);  // nothing ran
}
