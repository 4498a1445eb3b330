// CollisionTotals: taken from either engine's counters field by field, and the step differences
// the LAMMPS fix forms (counters after minus before) add back up to the totals.
#include <gtest/gtest.h>

#include "hardsphere/collision_totals.hpp"
#include "hardsphere/simulation.hpp"

using namespace hardsphere;

TEST(CollisionTotals, TakesEveryFieldFromTheStepperCounters) {
  StepCounters c;
  c.collisions = 7, c.wall_collisions = 3, c.resting_contacts = 2, c.pair_virial = 1.5;
  c.pair_virial_tensor = {1, 2, 3, 4, 5, 6}, c.wall_impulse = {0.5, 0.25, 0.125};
  c.dissipated_normal = 0.75, c.dissipated_tangential = 0.375;
  const CollisionTotals t = collision_totals(c);
  EXPECT_EQ(t.collisions, 7);
  EXPECT_EQ(t.wall_collisions, 3);
  EXPECT_EQ(t.resting_contacts, 2);
  EXPECT_EQ(t.pair_virial, 1.5);
  EXPECT_EQ(t.pair_virial_tensor, c.pair_virial_tensor);
  EXPECT_EQ(t.wall_impulse, c.wall_impulse);
  EXPECT_EQ(t.dissipated_normal, 0.75);
  EXPECT_EQ(t.dissipated_tangential, 0.375);
  const RunTotals r = run_totals(c, 2.0, {1, 0, 0});  // the run summary's totals hold the same
  EXPECT_EQ(r.collisions, 7);
  EXPECT_EQ(r.pair_virial_tensor, c.pair_virial_tensor);
  EXPECT_EQ(r.kinetic_energy_initial, 2.0);
}

TEST(CollisionTotals, EventCountersHaveNoVirialTensor) {
  EventCounters c;
  c.collisions = 4, c.wall_collisions = 1, c.resting_contacts = 5, c.pair_virial = 2.5, c.wall_impulse = {1, 2, 3};
  const WeightedCollisionTotals t = collision_totals<double>(c);
  EXPECT_EQ(t.collisions, 4.0);
  EXPECT_EQ(t.wall_collisions, 1.0);
  EXPECT_EQ(t.resting_contacts, 5.0);
  EXPECT_EQ(t.pair_virial, 2.5);
  EXPECT_EQ(t.pair_virial_tensor, (std::array<double, 6>{0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(t.wall_impulse, (std::array<double, 3>{1, 2, 3}));
}

TEST(CollisionTotals, StepDifferencesSumToTheTotals) {
  CollisionTotals before, after;
  before.collisions = 10, before.wall_collisions = 2, before.resting_contacts = 1, before.pair_virial = 3;
  before.pair_virial_tensor = {1, 1, 1, 0, 0, 0}, before.wall_impulse = {1, 0, 0}, before.dissipated_normal = 0.5;
  after = before;
  after.collisions += 5, after.wall_collisions += 1, after.pair_virial += 2, after.pair_virial_tensor[4] = 0.5;
  after.wall_impulse[2] = 0.25, after.dissipated_tangential = 0.125;
  const CollisionTotals step = after - before;
  EXPECT_EQ(step.collisions, 5);
  EXPECT_EQ(step.wall_collisions, 1);
  EXPECT_EQ(step.resting_contacts, 0);
  EXPECT_EQ(step.pair_virial, 2);
  EXPECT_EQ(step.pair_virial_tensor, (std::array<double, 6>{0, 0, 0, 0, 0.5, 0}));
  EXPECT_EQ(step.wall_impulse, (std::array<double, 3>{0, 0, 0.25}));
  EXPECT_EQ(step.dissipated_normal, 0);
  EXPECT_EQ(step.dissipated_tangential, 0.125);
  CollisionTotals sum = before;
  sum += step;
  EXPECT_EQ(sum.collisions, after.collisions);
  EXPECT_EQ(sum.wall_collisions, after.wall_collisions);
  EXPECT_EQ(sum.pair_virial, after.pair_virial);
  EXPECT_EQ(sum.pair_virial_tensor, after.pair_virial_tensor);
  EXPECT_EQ(sum.wall_impulse, after.wall_impulse);
  EXPECT_EQ(sum.dissipated_tangential, after.dissipated_tangential);
}
