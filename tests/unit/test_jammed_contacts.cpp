// Jammed contact chains: spheres exactly at contact in a closed chain with approaching velocities
// take infinitely many collisions at one instant. Both engines refuse them with a message naming
// atoms of the chain, in bounded time; an open chain (Newton's cradle) still runs.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

//! Two unit spheres stacked between walls two diameters apart, touching each other and both
//! walls, pressed together.
ParticleSystem pressed_between_walls() {
  ParticleSystem s;
  s.box = Box::from_lengths({4, 4, 2}, {true, true, false});
  s.push_back(1, 1, 0.5, 1.0, {2, 2, 0.5}, {0.1, 0, 1});
  s.push_back(2, 1, 0.5, 1.0, {2, 2, 1.5}, {0, 0.2, -1});
  return s;
}

//! A periodic simple cubic lattice of k^3 unit spheres at contact, random velocities.
ParticleSystem cubic_lattice_at_contact(int k) {
  ParticleSystem s;
  s.box = Box::from_lengths({double(k), double(k), double(k)}, {true, true, true});
  std::mt19937_64 rng(3);
  std::normal_distribution<double> v;
  std::int64_t id = 0;
  for (int x = 0; x < k; ++x)
    for (int y = 0; y < k; ++y)
      for (int z = 0; z < k; ++z) s.push_back(++id, 1, 0.5, 1.0, {x + 0.5, y + 0.5, z + 0.5}, {v(rng), v(rng), v(rng)});
  return s;
}

std::string stepper_refusal(const ParticleSystem& s, const Physics& physics = {}, const PhysicsNames& names = {}) {
  StepperConfig cfg;
  cfg.dt = 0.01;
  cfg.names = names;
  try {
    make_stepper(s, physics, cfg)->run(5);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string event_refusal(const ParticleSystem& s, const Physics& physics = {}, const PhysicsNames& names = {}) {
  EventConfig cfg;
  cfg.max_events = 1e7;  // far above the jam bound: a hang is refused rather than waited for
  cfg.names = names;
  try {
    EventEngine(s, physics, cfg).advance(0.05);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(JammedContacts, TwoSpheresPressedBetweenWallsAreRefusedByBothEngines) {
  EXPECT_NE(stepper_refusal(pressed_between_walls()).find("stepper: jammed spheres: atoms "), std::string::npos);
  EXPECT_NE(event_refusal(pressed_between_walls()).find("event engine: jammed spheres: atoms "), std::string::npos);
}

TEST(JammedContacts, CubicLatticeAtContactIsRefusedByBothEngines) {
  for (const std::string& m :
       {stepper_refusal(cubic_lattice_at_contact(4)), event_refusal(cubic_lattice_at_contact(4))})
    EXPECT_NE(m.find("jammed spheres: atoms "), std::string::npos) << m;
}

// With inelastic collisions a pile-up at one instant may be a collapse that a longer contact time
// lets through: the refusal names that setting as the face names it (issue 42, item 6).
TEST(JammedContacts, InelasticRefusalsNameTheContactTimeInTheFacesWords) {
  Physics inelastic;
  inelastic.restitution = 0.2, inelastic.contact_time = 1e-4;
  for (const char* tc : {"--contact-time", "contact_time"}) {
    PhysicsNames names;
    names.restitution = tc[0] == '-' ? "--restitution" : "restitution", names.contact_time = tc;
    const std::string advice = names.restitution +
                               " 0.2 it may also be an inelastic collapse (spheres settling "
                               "onto each other, their collisions ever closer in time), which a longer " +
                               std::string(tc) + " lets through: give e.g. " + tc + " 0.001 (now 0.0001;";
    for (const std::string& m : {stepper_refusal(pressed_between_walls(), inelastic, names),
                                 event_refusal(pressed_between_walls(), inelastic, names)}) {
      EXPECT_NE(m.find("jammed spheres: atoms "), std::string::npos) << m;
      EXPECT_NE(m.find(advice), std::string::npos) << m;
    }
  }
  // Inelastic walls only: the advice names the wall's restitution, not the pairs' 1.
  Physics walls;
  walls.contact_time = 1e-4, walls.walls[4].restitution = walls.walls[5].restitution = 0.5;
  PhysicsNames cli;
  cli.wall_restitution = "--wall-restitution", cli.contact_time = "--contact-time";
  for (const std::string& m :
       {stepper_refusal(pressed_between_walls(), walls, cli), event_refusal(pressed_between_walls(), walls, cli)})
    EXPECT_NE(m.find("; with --wall-restitution zlo=0.5 it may also be an inelastic collapse"), std::string::npos) << m;
  // Elastic collisions cannot collapse: no such advice.
  EXPECT_EQ(stepper_refusal(pressed_between_walls()).find("inelastic collapse"), std::string::npos);
}

// Events at one instant that are one sphere's list rebuilds: no chain and no wall, a sphere too
// fast for the clock, named with its speed (issue 42, item 15).
TEST(JammedContacts, ASphereTooFastForTheClockIsNamedWithItsSpeed) {
  // Perfectly rough: the collision at t = 1 turns the spin into a speed of ~3e19, whose list
  // rebuilds at ~2e-20 apart the clock no longer tells apart.
  ParticleSystem s = test::two({2, 5, 5}, {1, 0, 0}, {5, 5, 5}, {-1, 0, 0});
  s.omega[0] = {0, 0, 1e20};
  Physics rough;
  rough.tangential_restitution = 1;
  EventConfig cfg;
  cfg.max_events = 1e7;
  std::string m;
  try {
    EventEngine(s, rough, cfg).advance(3.0);
  } catch (const InputError& e) {
    m = e.what();
  }
  EXPECT_NE(m.find("took more than 10200 events at one instant (time 1"), std::string::npos) << m;
  EXPECT_NE(m.find(", it rebuilds its neighbour list every"), std::string::npos) << m;
  EXPECT_EQ(m.find("wall"), std::string::npos) << m;
}

TEST(JammedContacts, OpenChainsAndLeavingPairsRun) {
  // Newton's cradle: three touching spheres, the first moving into them: two collisions, then
  // the last one leaves. Pressed spheres with room above: they part.
  const ParticleSystem cradle = [] {
    ParticleSystem s;
    s.box = Box::from_lengths({10, 10, 10}, {true, true, true});
    for (int k = 0; k < 3; ++k) s.push_back(k + 1, 1, 0.5, 1.0, {3.0 + k, 5, 5}, {k == 0 ? 1.0 : 0.0, 0, 0});
    return s;
  }();
  ParticleSystem roomy = pressed_between_walls();
  roomy.box = Box::from_lengths({4, 4, 2.5}, {true, true, false});
  for (const ParticleSystem& s : {cradle, roomy}) {
    EXPECT_EQ(stepper_refusal(s), "");
    EXPECT_EQ(event_refusal(s), "");
  }
}
