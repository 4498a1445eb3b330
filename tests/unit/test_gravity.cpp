// Gravity in both engines: exact parabolic flights and wall bounces, the barometric profile of an
// elastic gas with kinetic + potential energy conserved, and a settled inelastic bed whose floor
// carries its weight.
#include <gtest/gtest.h>

#include <cmath>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

StepperConfig steps_of(double dt) {
  StepperConfig cfg;
  cfg.dt = dt;
  return cfg;
}

Physics falling(double g) {
  Physics p;
  p.gravity = {0.0, 0.0, -g};
  return p;
}

ParticleSystem gas_between_floor_and_ceiling(std::int64_t n, double side, double height, std::uint64_t seed) {
  InitSpec spec;
  spec.n = n;
  spec.box = Box::from_lengths({side, side, height}, {true, true, false});
  spec.seed = seed;
  return make_initial_state(spec);
}

}  // namespace

TEST(Gravity, DroppedSphereBouncesOnAnExactParabola) {
  // Unit sphere dropped from rest 5 above its floor contact, g = 1: it lands at t1 = sqrt(10)
  // with speed sqrt(10) and rises again; at t = 5 it is at 0.5 + sqrt(10) (t - t1) - (t - t1)^2 / 2.
  ParticleSystem s =
      test::two({2.0, 2.0, 5.5}, {0, 0, 0}, {7.0, 7.0, 0.82}, {0, 0, 0}, 0.5, 0.5, 1, 1, 10.0, {true, true, false});
  auto st = make_stepper(s, falling(1.0), steps_of(0.01));
  st->run(500);
  const ParticleSystem out = st->state();
  const double t1 = std::sqrt(10.0), u = 5.0 - t1;
  EXPECT_NEAR(out.pos[0].z, 0.5 + std::sqrt(10.0) * u - 0.5 * u * u, 1e-9);
  EXPECT_NEAR(out.vel[0].z, std::sqrt(10.0) - u, 1e-9);
  // The other sphere, 0.32 above its contact, lands at t = 0.8, 2.4 and 4.0 with speed 0.8.
  EXPECT_EQ(st->counters().wall_collisions, 4);
  // The momentum the floor took: 2 m v at each landing.
  EXPECT_NEAR(st->counters().wall_impulse[2], 2.0 * std::sqrt(10.0) + 3 * 2.0 * 0.8, 1e-9);
}

TEST(Gravity, ElasticGasSettlesIntoTheBarometricProfileAndKeepsItsEnergy) {
  // Dilute gas (phi ~0.01 at the floor), scale height T / (m g) = 20 in a box 100 tall: the
  // mean height above the floor contact is h - H' / (exp(H'/h) - 1), H' = H - 2r, with T the
  // measured temperature; kinetic + potential energy is kept to 1e-9. With 1500 spheres the
  // measured mean height spreads by ~0.7% over seeds: the 3% bound is over 4 of those.
  const double g = 0.05, height = 100.0, n = 1500;
  ParticleSystem s = gas_between_floor_and_ceiling(std::int64_t(n), 67.0, height, 4);
  auto st = make_stepper(s, falling(g), steps_of(0.05));
  const double e0 = kinetic_energy(s) + potential_energy(s, {0, 0, -g});
  st->run(8000);  // equilibrate: ~400 time units, several sound crossings
  double sum_z = 0, sum_t = 0;
  int samples = 0;
  for (int k = 0; k < 200; ++k) {
    st->run(100);
    const ParticleSystem now = st->state();
    for (std::size_t i = 0; i < now.size(); ++i) sum_z += now.pos[i].z - 0.5;
    sum_t += temperature(now);
    ++samples;
  }
  const ParticleSystem fin = st->state();
  EXPECT_LT(std::abs(kinetic_energy(fin) + potential_energy(fin, {0, 0, -g}) - e0) / e0, 1e-9);
  const double t = sum_t / samples, h = t / g, hp = height - 1.0;
  const double expected = h - hp / std::expm1(hp / h);
  EXPECT_NEAR(sum_z / (samples * n) / expected, 1.0, 0.03) << "T " << t;
}

TEST(Gravity, InelasticSpheresSettleIntoABedThatTheFloorCarries) {
  // e = 0.5, g = 1: the gas collapses onto the floor into a packed bed (TC model keeps it
  // running); no pair overlaps, and once settled the floor takes the bed's weight N m g (over 10
  // seeds force / weight had mean 1.0007 and sd 0.05%).
  ParticleSystem s = gas_between_floor_and_ceiling(300, 8.0, 30.0, 6);
  const StepperConfig cfg = steps_of(0.005);
  Physics cfg_physics = falling(1.0);
  cfg_physics.restitution = 0.5;
  cfg_physics.contact_time = kDefaultContactTime;
  auto st = make_stepper(s, cfg_physics, cfg);
  st->run(3000);  // 15 time units: settled
  const double before = st->counters().wall_impulse[2];
  st->run(1000);
  const double force = (st->counters().wall_impulse[2] - before) / 5.0;
  const ParticleSystem fin = st->state();
  EXPECT_LT(max_overlap(fin), 1e-9);
  EXPECT_LT(temperature(fin), 0.05);
  EXPECT_NEAR(force / 300.0, 1.0, 0.02);
  EXPECT_EQ(st->counters().unresolved_steps, 0);
}

TEST(Gravity, EventEngineFliesTheSameParabolas) {
  ParticleSystem s =
      test::two({2.0, 2.0, 5.5}, {0, 0, 0}, {7.0, 7.0, 0.82}, {0, 0, 0}, 0.5, 0.5, 1, 1, 10.0, {true, true, false});
  EventConfig cfg;
  Physics cfg_physics;
  cfg_physics.gravity = {0, 0, -1};
  EventEngine e(s, cfg_physics, cfg);
  e.advance(5.0);
  const ParticleSystem out = e.state();
  const double t1 = std::sqrt(10.0), u = 5.0 - t1;
  EXPECT_NEAR(out.pos[0].z, 0.5 + std::sqrt(10.0) * u - 0.5 * u * u, 1e-9);
  EXPECT_NEAR(out.vel[0].z, std::sqrt(10.0) - u, 1e-9);
  EXPECT_EQ(e.counters().wall_collisions, 4);
  EXPECT_NEAR(e.counters().wall_impulse[2], 2.0 * std::sqrt(10.0) + 3 * 2.0 * 0.8, 1e-9);
}

TEST(Gravity, EventEngineGasKeepsItsEnergyAndItsBedLoadsTheFloor) {
  // Elastic: kinetic + potential energy kept to 1e-9 while the gas falls and mixes; inelastic
  // (e = 0.5): a settled bed without overlap whose floor takes its weight (over 10 seeds force /
  // weight had mean 1.0025 and sd 0.19%: |mean| + 4 sd = 1.0%).
  {
    const ParticleSystem s = gas_between_floor_and_ceiling(300, 10.0, 30.0, 8);
    EventConfig cfg;
    Physics cfg_physics;
    cfg_physics.gravity = {0, 0, -1};
    EventEngine e(s, cfg_physics, cfg);
    e.advance(20.0);
    const ParticleSystem fin = e.state();
    const double e0 = kinetic_energy(s) + potential_energy(s, cfg_physics.gravity);
    EXPECT_LT(std::abs(kinetic_energy(fin) + potential_energy(fin, cfg_physics.gravity) - e0) / e0, 1e-9);
    EXPECT_LT(max_overlap(fin), 1e-9);
  }
  const ParticleSystem s = gas_between_floor_and_ceiling(150, 6.0, 20.0, 9);
  EventConfig cfg;
  Physics cfg_physics;
  cfg_physics.gravity = {0, 0, -1};
  cfg_physics.restitution = 0.5;
  cfg_physics.contact_time = kDefaultContactTime;
  EventEngine e(s, cfg_physics, cfg);
  e.advance(10.0);
  const double before = e.counters().wall_impulse[2];
  e.advance(5.0);
  const double force = (e.counters().wall_impulse[2] - before) / 5.0;
  EXPECT_LT(max_overlap(e.state()), 1e-9);
  EXPECT_NEAR(force / 150.0, 1.0, 0.02);
}
