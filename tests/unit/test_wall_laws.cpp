// Wall laws (Physics::walls), both engines: a sphere dropped on a floor with restitution e_w
// rebounds at e_w^k v0 and comes to rest there; a rough sphere launched sliding on a floor with
// friction mu_w is braked at mu_w g until it rolls at v0 / (1 + q); what the walls took closes
// the energy budget. Their refusals are in test_physics.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/stepper.hpp"

using namespace hardsphere;

namespace {

constexpr double kG = 1.0, kDt = 0.01, kH0 = 4.5;  // dropped 4.5 above the contact: v0 = 3
constexpr int kZlo = 4;                            // Physics::walls index of the floor

//! One unit sphere (radius 0.5, mass 1) in a 10^3 box with walls along z only.
ParticleSystem one_sphere(Vec3d pos, Vec3d vel, Vec3d omega = {}) {
  ParticleSystem s;
  s.box = Box::from_lengths({10, 10, 10}, {true, true, false});
  s.push_back(1, 1, 0.5, 1.0, pos, vel, {0, 0, 0}, omega);
  return s;
}

Physics floor_with(double e_w) {
  Physics p;
  p.gravity = {0, 0, -kG};
  p.contact_time = kDefaultContactTime;
  p.walls[std::size_t(kZlo)].restitution = e_w;
  return p;
}

//! The energy per unit mass above the floor's contact plane (z = 0.5), rotation included.
double energy(const ParticleSystem& s, double q = 0.4) {
  const Vec3d v = s.vel[0], w = s.omega.empty() ? Vec3d{} : s.omega[0];
  return 0.5 * dot(v, v) + 0.5 * q * 0.25 * dot(w, w) + kG * (s.pos[0].z - 0.5);
}

//! The flight energies after each bounce, sampled every `every` of time (the flight conserves
//! it): one per wall collision counted.
template <class Engine, class Advance, class Bounces>
std::vector<double> rebound_energies(Engine& e, Advance advance, Bounces bounces, int samples) {
  std::vector<double> out;
  std::int64_t seen = 0;
  for (int k = 0; k < samples; ++k) {
    advance(e);
    const std::int64_t b = bounces(e);
    if (b == seen) continue;
    EXPECT_EQ(b, seen + 1) << "two bounces in one sample";
    seen = b;
    out.push_back(energy(e.state()));
  }
  return out;
}

//! Rebound k leaves at e_w^k v0: its flight energy is (e_w^k v0)^2 / 2, to rounding.
void expect_rebounds(const std::vector<double>& energies, double e_w, std::size_t at_least) {
  ASSERT_GE(energies.size(), at_least);
  const double v0 = std::sqrt(2 * kG * kH0);
  for (std::size_t k = 0; k < at_least; ++k) {
    const double v = v0 * std::pow(e_w, double(k + 1));
    EXPECT_NEAR(energies[k], 0.5 * v * v, 1e-12 * 0.5 * v0 * v0) << "bounce " << k + 1;
  }
}

}  // namespace

TEST(WallLaws, DroppedSphereReboundsAtEwToTheKThenRestsInTheStepper) {
  // Rebounds at 1.5, 0.75, ... rest once the arrival is below g dt = 0.01 (the 8th: 0.0117, 9th:
  // 0.0059); the bounces end by t = 3 + 2 (1.5 + 0.75 + ...) / g = 9.
  for (const double e_w : {0.5, 0.8}) {
    StepperConfig cfg;
    cfg.dt = kDt;
    auto st = make_stepper(one_sphere({5, 5, 0.5 + kH0}, {}), floor_with(e_w), cfg);
    const double e0 = energy(st->state());
    const auto energies = rebound_energies(
        *st, [](StepperBase& s) { s.run(1); }, [](StepperBase& s) { return s.counters().wall_collisions; }, 6000);
    expect_rebounds(energies, e_w, e_w == 0.5 ? 8 : 20);
    const ParticleSystem end = st->state();  // t = 60: on the floor, hopping below g dt^2
    EXPECT_GE(end.pos[0].z, 0.5 - 1e-12);
    EXPECT_LE(end.pos[0].z, 0.5 + kG * kDt * kDt);
    EXPECT_LE(std::abs(end.vel[0].z), kG * kDt);
    EXPECT_GT(st->counters().resting_contacts, 0);
    // What the floor took is the energy lost (restitution and the resting contacts' hops).
    const StepCounters& c = st->counters();
    EXPECT_NEAR(e0 - energy(end), c.wall_dissipated_normal + c.wall_dissipated_tangential, 1e-12 * e0);
  }
}

TEST(WallLaws, DroppedSphereReboundsAtEwToTheKThenRestsInTheEventEngine) {
  for (const double e_w : {0.5, 0.8}) {
    EventConfig cfg;
    cfg.max_events = 1e6;
    EventEngine e(one_sphere({5, 5, 0.5 + kH0}, {}), floor_with(e_w), cfg);
    const double e0 = energy(e.state());
    // The resting threshold g tau = 0.01 (tau = kRestingTimeFraction): as the stepper's.
    const auto energies = rebound_energies(
        e, [](EventEngine& x) { x.advance(kDt); }, [](EventEngine& x) { return x.counters().wall_collisions; }, 6000);
    expect_rebounds(energies, e_w, e_w == 0.5 ? 8 : 20);
    const ParticleSystem end = e.state();
    EXPECT_GE(end.pos[0].z, 0.5 - 1e-12);
    EXPECT_LE(end.pos[0].z, 0.5 + kG * kRestingTimeFraction * kRestingTimeFraction);
    EXPECT_GT(e.counters().resting_contacts, 0);
    const EventCounters& c = e.counters();
    EXPECT_NEAR(e0 - energy(end), c.wall_dissipated_normal + c.wall_dissipated_tangential, 1e-12 * e0);
  }
}

namespace {

//! A rough sphere (q = 0.4) on the floor launched along x at v0 = 2 without spin, mu_w = 0.2:
//! friction brakes it at mu_w g while its spin grows at mu_w g / (q a) until the contact point
//! sticks, at t* = q v0 / ((1 + q) mu_w g) = 20/7, then it rolls at v0 / (1 + q) = 10/7 (its
//! angular momentum about the contact point is kept). The normal impulse the resting contacts
//! give over a time t is g t to within one hop's g h (h: dt, or the event engine's tau), so the
//! speed is mu_w g t off by at most mu_w g h.
constexpr double kV0 = 2, kMu = 0.2, kQ = 0.4;

Physics rough_floor() {
  Physics p = floor_with(1.0);
  p.tangential_restitution = 0.5;
  p.walls[std::size_t(kZlo)].tangential_restitution = 0.5;
  p.walls[std::size_t(kZlo)].friction = kMu;
  return p;
}

template <class Engine, class Advance>
void expect_slides_then_rolls(Engine& e, Advance advance, double hop) {
  const double t_roll = kQ * kV0 / ((1 + kQ) * kMu * kG), v_roll = kV0 / (1 + kQ);
  const double tol = kMu * kG * hop + 1e-12;
  double t = 0;
  for (; t < 2.0 - 1e-9; t += kDt) advance(e);  // sliding: v0 - mu g t
  ParticleSystem s = e.state();
  EXPECT_NEAR(s.vel[0].x, kV0 - kMu * kG * t, tol);
  EXPECT_NEAR(s.omega[0].y, kMu * kG * t / (kQ * 0.5), tol / (kQ * 0.5));
  for (; t < 8.0 - 1e-9; t += kDt) advance(e);
  s = e.state();
  EXPECT_NEAR(s.vel[0].x, v_roll, tol);
  EXPECT_NEAR(s.omega[0].y * 0.5, s.vel[0].x, 1e-9);  // rolling: the contact point at rest
  EXPECT_NEAR(s.vel[0].y, 0.0, 1e-15);
  // It rolled from t*: the distance is that of braking to t*, then v_roll.
  const double x_roll = kV0 * t_roll - 0.5 * kMu * kG * t_roll * t_roll + v_roll * (t - t_roll);
  EXPECT_NEAR(s.pos[0].x - 5 + 10 * double(s.image[0][0]), x_roll, tol * t);
  EXPECT_LE(std::abs(s.pos[0].z - 0.5), kG * hop * hop);
}

}  // namespace

TEST(WallLaws, RoughSphereSlidesAtMuGThenRollsInTheStepper) {
  StepperConfig cfg;
  cfg.dt = kDt;
  auto st = make_stepper(one_sphere({5, 5, 0.5}, {kV0, 0, 0}), rough_floor(), cfg);
  const double e0 = energy(st->state());
  expect_slides_then_rolls(
      *st, [](StepperBase& s) { s.run(1); }, kDt);
  const StepCounters& c = st->counters();
  EXPECT_GT(c.wall_dissipated_tangential, 0.0);
  EXPECT_NEAR(e0 - energy(st->state()), c.wall_dissipated_normal + c.wall_dissipated_tangential, 1e-12 * e0);
}

TEST(WallLaws, RoughSphereSlidesAtMuGThenRollsInTheEventEngine) {
  EventConfig cfg;
  cfg.max_events = 1e6;
  EventEngine e(one_sphere({5, 5, 0.5}, {kV0, 0, 0}), rough_floor(), cfg);
  const double e0 = energy(e.state());
  expect_slides_then_rolls(
      e, [](EventEngine& x) { x.advance(kDt); }, kRestingTimeFraction);
  const EventCounters& c = e.counters();
  EXPECT_GT(c.wall_dissipated_tangential, 0.0);
  EXPECT_NEAR(e0 - energy(e.state()), c.wall_dissipated_normal + c.wall_dissipated_tangential, 1e-12 * e0);
}
