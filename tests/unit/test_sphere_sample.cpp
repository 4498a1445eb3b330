// Per-sphere pair-collision counts and the one-sphere accessor (the CLI tracker's source) in
// both engines: counts add up to twice the collision total, and a sample equals the sphere's
// entry in the full state.
#include <gtest/gtest.h>

#include <numeric>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

namespace hardsphere {
namespace {

// A big sphere (id 1) in a gas: the scene the tracker is for, with unequal radii and masses.
ParticleSystem big_in_gas() {
  ParticleSystem s = test::gas(400, 0.1, 17);
  s.radius[0] = 1.5;
  s.mass[0] = 27;
  // Make room for the big sphere: drop the small spheres it would overlap.
  ParticleSystem out;
  out.box = s.box;
  for (std::size_t i = 0; i < s.size(); ++i) {
    Vec3d d = s.pos[i] - s.pos[0];
    for (int k = 0; k < 3; ++k) d[k] -= s.box.length(k) * std::nearbyint(d[k] / s.box.length(k));
    if (i == 0 || norm(d) > s.radius[0] + s.radius[i] + 1e-9)
      out.push_back(s.id[i], s.type[i], s.radius[i], s.mass[i], s.pos[i], s.vel[i]);
  }
  return out;
}

void expect_sample_matches(const SphereSample& a, const ParticleSystem& st, std::size_t i, double tol) {
  for (int d = 0; d < 3; ++d) {
    const double unwrapped = st.pos[i][d] + double(st.image[i][d]) * st.box.length(d);
    EXPECT_NEAR(a.unwrapped[d], unwrapped, tol) << "sphere " << st.id[i] << " axis " << d;
    EXPECT_EQ(a.velocity[d], st.vel[i][d]);
  }
}

TEST(SphereSample, StepperCountsAddUpAndSampleMatchesState) {
  const ParticleSystem sys = big_in_gas();
  StepperConfig cfg;
  cfg.dt = 0.02;
  cfg.count_per_sphere = true;
  auto engine = make_stepper(sys, {}, cfg);
  engine->run(50);
  engine->reset_counters();
  engine->run(300);
  const auto counts = engine->pair_collisions_per_sphere();
  ASSERT_EQ(counts.size(), sys.size());
  ASSERT_GT(engine->counters().collisions, 1000);
  EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), std::int64_t(0)), 2 * engine->counters().collisions);
  const ParticleSystem st = engine->state();
  for (std::size_t i = 0; i < st.size(); ++i) {
    const SphereSample a = engine->sphere(i);
    expect_sample_matches(a, st, i, 1e-9);
    EXPECT_EQ(a.pair_collisions, counts[i]);
  }
  // The big sphere meets more spheres: over 10 seeds it had 21 more collisions than sphere 2,
  // sd 3.2 (6.6 sd).
  EXPECT_GT(counts[0], counts[1]);
  EXPECT_THROW(engine->sphere(st.size()), InputError);
}

// Uncounted (the default), the stepper runs the same collisions and says it did not count.
TEST(SphereSample, StepperWithoutCountsRunsTheSameCollisions) {
  const ParticleSystem sys = big_in_gas();
  StepperConfig cfg;
  cfg.dt = 0.02;
  auto plain = make_stepper(sys, {}, cfg);
  cfg.count_per_sphere = true;
  auto counted = make_stepper(sys, {}, cfg);
  plain->run(200);
  counted->run(200);
  EXPECT_EQ(plain->counters().collisions, counted->counters().collisions);
  EXPECT_TRUE(plain->pair_collisions_per_sphere().empty());
  EXPECT_EQ(plain->sphere(0).pair_collisions, -1);
  EXPECT_EQ(plain->sphere(0).unwrapped.x, counted->sphere(0).unwrapped.x);
}

TEST(SphereSample, EventEngineCountsAddUpAndSampleMatchesState) {
  const ParticleSystem sys = big_in_gas();
  EventEngine engine(sys);
  engine.advance(1);
  engine.reset_counters();
  engine.advance(6.0);
  const auto counts = engine.pair_collisions_per_sphere();
  ASSERT_EQ(counts.size(), sys.size());
  ASSERT_GT(engine.counters().collisions, 1000);
  EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), std::int64_t(0)), 2 * engine.counters().collisions);
  const ParticleSystem st = engine.state();
  for (std::size_t i = 0; i < st.size(); ++i) {
    const SphereSample a = engine.sphere(i);
    expect_sample_matches(a, st, i, 1e-9);
    EXPECT_EQ(a.pair_collisions, counts[i]);
  }
  EXPECT_GT(counts[0], counts[1]);
  EXPECT_THROW(engine.sphere(st.size()), InputError);
}

// The two engines follow the same trajectory of the big sphere over a short time: its
// collisions and its unwrapped path agree (exact dynamics, rounding aside).
TEST(SphereSample, EnginesAgreeOnTheTrackedSphere) {
  const ParticleSystem sys = big_in_gas();
  StepperConfig cfg;
  cfg.dt = 0.01;
  cfg.count_per_sphere = true;
  auto stepper = make_stepper(sys, {}, cfg);
  EventEngine event(sys);
  stepper->run(100);
  event.advance(1.0);
  const std::size_t big_in_stepper = 0, big_in_event = 0;  // id 1 is first in both orders
  const SphereSample a = stepper->sphere(big_in_stepper), b = event.sphere(big_in_event);
  EXPECT_EQ(a.pair_collisions, b.pair_collisions);
  EXPECT_GT(a.pair_collisions, 0);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(a.unwrapped[d], b.unwrapped[d], 1e-6);
}

}  // namespace
}  // namespace hardsphere
