// Transport integrals (transport.hpp): the stress and heat-flux moments both engines feed are the
// exact time integrals of a known collision, the engines agree on a gas, and scenes without
// equilibrium transport coefficients are refused naming the value.
#include <gtest/gtest.h>

#include <cmath>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/stepper.hpp"
#include "hardsphere/transport.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

// Two unit spheres meet once within t = 3 (across the periodic face only after t = 4). The
// expectation is worked out here from first principles: the contact time of the straight paths,
// the elastic exchange along the centre line n, K and J before and after, and n (x) dp, n dE.
ParticleSystem pair() { return test::two({2.05, 5, 5}, {1, 0.5, 0}, {5, 5, 5}, {-1, 0, 0.3}); }

void expect_pair(const TransportMoments& m) {
  Vec3d x1{2.05, 5, 5}, v1{1, 0.5, 0}, x2{5, 5, 5}, v2{-1, 0, 0.3};
  const Vec3d dr = x1 - x2, dv = v1 - v2;
  const double a = dot(dv, dv), b = dot(dr, dv), c = dot(dr, dr) - 1;
  const double tc = (-b - std::sqrt(b * b - a * c)) / a, total = 3;
  const Vec3d n = dr + tc * dv;  // |n| = 1 at contact
  const double w = dot(dv, n);
  const Vec3d u1 = v1 - w * n, u2 = v2 + w * n;
  auto k = [](Vec3d p, Vec3d q) {
    return std::array<double, 6>{p.x * p.x + q.x * q.x, p.y * p.y + q.y * q.y, p.z * p.z + q.z * q.z,
                                 p.x * p.y + q.x * q.y, p.x * p.z + q.x * q.z, p.y * p.z + q.y * q.z};
  };
  auto j = [](Vec3d p, Vec3d q) { return 0.5 * dot(p, p) * p + 0.5 * dot(q, q) * q; };
  const auto k0 = k(v1, v2), k1 = k(u1, u2);
  const Vec3d dp = u1 - v1, j0 = j(v1, v2), j1 = j(u1, u2);
  const double de = 0.5 * (dot(u1, u1) - dot(v1, v1));
  const double rdp[6] = {n.x * dp.x, n.y * dp.y, n.z * dp.z, n.x * dp.y, n.x * dp.z, n.y * dp.z};
  ASSERT_GT(tc, 0.5);
  ASSERT_GT(std::abs(de), 0.1);  // energy changes hands: the collisional heat term is tested
  EXPECT_NEAR(m.time, total, 1e-12);
  for (std::size_t q = 0; q < 6; ++q)
    EXPECT_NEAR(m.stress[q], k0[q] * tc + k1[q] * (total - tc) + rdp[q], 1e-12) << "stress component " << q;
  for (int q = 0; q < 3; ++q)
    EXPECT_NEAR(m.heat[std::size_t(q)], j0[q] * tc + j1[q] * (total - tc) + n[q] * de, 1e-12) << "heat " << q;
}

}  // namespace

TEST(Transport, StepperIntegratesACollisionExactly) {
  const ParticleSystem s = pair();
  StepperConfig cfg;
  cfg.dt = 0.1;
  auto engine = make_stepper(s, {}, cfg);
  TransportTally tally;
  tally.start(engine->state());
  engine->set_transport(&tally);
  engine->run(30);
  EXPECT_EQ(engine->counters().collisions, 1);
  expect_pair(tally.moments());
}

TEST(Transport, EventEngineIntegratesACollisionExactly) {
  const ParticleSystem s = pair();
  EventEngine engine(s);
  TransportTally tally;
  tally.start(engine.state());
  engine.set_transport(&tally);
  engine.advance(1.5);
  engine.advance(1.5);
  EXPECT_EQ(engine.counters().collisions, 1);
  expect_pair(tally.moments());
}

// A dense gas over a few collisions per sphere: both engines resolve the same collisions, so their
// moments agree to rounding; long steps (dt = 0.05 at phi 0.35) make the stepper split and cut steps.
// The collisional trace is the collision virial the counters keep.
TEST(Transport, BothEnginesAgreeOnADenseGas) {
  const ParticleSystem s = test::gas(300, 0.35, 7);
  StepperConfig cfg;
  cfg.dt = 0.05;
  cfg.detect = Detect::Sweep;  // overlap detection would miss grazes the event engine resolves
  auto stepper = make_stepper(s, {}, cfg);
  TransportTally a, b;
  a.start(s);
  stepper->set_transport(&a);
  stepper->run(20);
  EventEngine event(s);
  b.start(s);
  event.set_transport(&b);
  event.advance(1.0);
  ASSERT_EQ(stepper->counters().collisions, event.counters().collisions);
  ASSERT_GT(event.counters().collisions, 1000);
  for (std::size_t k = 0; k < 6; ++k)
    EXPECT_NEAR(a.moments().stress[k], b.moments().stress[k], 1e-9 * std::abs(b.moments().stress[0])) << "stress " << k;
  for (std::size_t k = 0; k < 3; ++k)
    EXPECT_NEAR(a.moments().heat[k], b.moments().heat[k], 1e-9 * std::abs(b.moments().stress[0])) << "heat " << k;
  // Trace: 2 E t (kinetic, E constant) + the collision virial.
  double e = 0;
  for (std::size_t i = 0; i < s.size(); ++i) e += 0.5 * s.mass[i] * dot(s.vel[i], s.vel[i]);
  const auto& m = b.moments();
  EXPECT_NEAR(m.stress[0] + m.stress[1] + m.stress[2], 2 * e * 1.0 + event.counters().pair_virial, 1e-9 * m.stress[0]);
}

TEST(Transport, ScenesWithoutEquilibriumCoefficientsAreRefused) {
  const ParticleSystem gas = test::gas(50, 0.1, 1);
  auto refused = [](const ParticleSystem& s, const Physics& p, const char* text) {
    try {
      check_transport(s, p, "--transport");
      ADD_FAILURE() << "not refused: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  EXPECT_NO_THROW(check_transport(gas, {}, "--transport"));
  refused(test::gas(50, 0.1, 1, std::nullopt, {true, true, false}), {}, "the z axis has walls");
  Physics g;
  g.gravity = {0, 0, -1};
  refused(gas, g, "gravity 0,0,-1");
  Physics e;
  e.restitution = 0.9;
  refused(gas, e, "restitution 0.9");
  Physics r;
  r.tangential_restitution = 0.5;
  refused(gas, r, "tangential restitution 0.5");
  ParticleSystem mix = gas;
  mix.radius[3] = 0.3;
  refused(mix, {}, "atom 4 has radius 0.3");
}
