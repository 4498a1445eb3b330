// Resting contacts under gravity, both engines: a sphere or a stack at rest on the floor stays at
// rest, the floor carries its weight, and the work per unit time stays constant as it rests. A
// resting contact passes at most m g (resting time) to the floor, so a column of n carries its
// weight with ~n of them per resting time (the stepper: per sub-step, up to twice) and ~n^2/2 pair collisions
// (docs/robustness.md).
#include <gtest/gtest.h>

#include <cmath>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

constexpr double kG = 1.0, kDt = 0.01;  // unit spheres: the event engine's tau = kRestingTimeFraction

Physics falling() {
  Physics p;
  p.gravity = {0.0, 0.0, -kG};
  return p;
}

//! Unit spheres (mass 1) stacked on the floor of a 10^3 box, periodic in x and y, at rest.
ParticleSystem stack(int n, double vz0 = 0.0) {
  ParticleSystem s;
  s.box = Box::from_lengths({10, 10, 10}, {true, true, false});
  for (int k = 0; k < n; ++k) s.push_back(k + 1, 1, 0.5, 1.0, {5, 5, 0.5 + k}, {0, 0, k == 0 ? vz0 : 0.0});
  return s;
}

std::unique_ptr<StepperBase> stepper_for(const ParticleSystem& s) {
  StepperConfig cfg;
  cfg.dt = kDt;
  return make_stepper(s, falling(), cfg);
}

EventEngine event_engine_for(const ParticleSystem& s) {
  EventConfig cfg;
  cfg.max_events = 1e6;  // a hang is refused rather than waited for
  return EventEngine(s, falling(), cfg);
}

//! Every sphere within `tol` of its resting height (never below the contact).
void expect_at_rest(const ParticleSystem& out, double tol) {
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_GE(out.pos[i].z, 0.5 + double(i) - 1e-12) << "sphere " << i;
    EXPECT_LE(out.pos[i].z, 0.5 + double(i) + tol) << "sphere " << i;
    EXPECT_LE(std::abs(out.vel[i].z), kG * kDt) << "sphere " << i;
  }
}

}  // namespace

TEST(RestingContacts, StepperSphereAndStackStayAtRestAndTheFloorCarriesTheirWeight) {
  for (int n : {1, 2, 5}) {
    auto st = stepper_for(stack(n));
    st->run(1000);  // t = 10
    const StepCounters first = st->counters();
    expect_at_rest(st->state(), kG * kDt * kDt);
    // The floor takes m g dt per step, half of it in the first (the sphere starts at rest).
    EXPECT_NEAR(first.wall_impulse[2] / (n * kG * 10.0), 1.0, kDt / 10.0) << n << " spheres";
    EXPECT_EQ(first.wall_collisions, 0);
    EXPECT_EQ(first.unresolved_steps, 0);
    EXPECT_LE(first.resting_contacts, 2 * n * 1000 + 1);
    EXPECT_LE(first.collisions, 3 * n * n * 1000 / 2);
    // At rest the work per step stays what it was: the next 1000 steps take as many events.
    st->run(1000);
    const StepCounters& both = st->counters();
    EXPECT_LE(both.resting_contacts - first.resting_contacts, first.resting_contacts * 11 / 10 + n);
    EXPECT_LE(both.collisions - first.collisions, first.collisions * 11 / 10 + n);
    expect_at_rest(st->state(), kG * kDt * kDt);
  }
}

TEST(RestingContacts, EventEngineSphereAndStackStayAtRestAndTheFloorCarriesTheirWeight) {
  const double tau = kRestingTimeFraction;
  for (int n : {1, 2, 5}) {
    EventEngine e = event_engine_for(stack(n));
    e.advance(10.0);
    const EventCounters first = e.counters();
    expect_at_rest(e.state(), kG * tau * tau);
    EXPECT_NEAR(first.wall_impulse[2] / (n * kG * 10.0), 1.0, 2 * tau / 10.0) << n << " spheres";
    EXPECT_EQ(first.wall_collisions, 0);
    EXPECT_LE(first.resting_contacts, std::int64_t(n * 10.0 / tau) + n);
    EXPECT_LE(first.collisions, std::int64_t(n * n * 10.0 / tau));
    e.advance(10.0);
    const EventCounters& both = e.counters();
    EXPECT_LE(both.events - first.events, first.events + 2 * n);
    expect_at_rest(e.state(), kG * tau * tau);
  }
}

TEST(RestingContacts, SpeedAtRoundingLevelIntoTheFloorRestsInBothEngines) {
  for (double vz : {-1e-16, 1e-16, -1e-300}) {
    auto st = stepper_for(stack(1, vz));
    st->run(100);
    expect_at_rest(st->state(), kG * kDt * kDt);
    EXPECT_LE(st->counters().resting_contacts, 201);
    EventEngine e = event_engine_for(stack(1, vz));
    e.advance(1.0);
    expect_at_rest(e.state(), kG * kRestingTimeFraction * kRestingTimeFraction);
    EXPECT_LE(e.counters().events, 2 * std::int64_t(1.0 / kRestingTimeFraction) + 4);
  }
}

TEST(RestingContacts, AFastLandingStillBouncesElastically) {
  // Dropped from 2 above the contact: it lands at speed 2 >> g dt and bounces back to that height.
  ParticleSystem s = stack(1);
  s.pos[0].z = 2.5;
  auto st = stepper_for(s);
  st->run(400);  // t = 4: one landing at t = 2, back at the top at t = 4
  EXPECT_EQ(st->counters().wall_collisions, 1);
  EXPECT_EQ(st->counters().resting_contacts, 0);
  EXPECT_NEAR(st->state().pos[0].z, 2.5, 1e-9);
  EventEngine e = event_engine_for(s);
  e.advance(4.0);
  EXPECT_EQ(e.counters().wall_collisions, 1);
  EXPECT_EQ(e.counters().resting_contacts, 0);
  EXPECT_NEAR(e.state().pos[0].z, 2.5, 1e-9);
}
