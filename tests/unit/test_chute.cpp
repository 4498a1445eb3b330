// Gravity along periodic axes (chutes) and gravity changed between steps, in both engines:
// a sphere on an inclined plane made by tilted gravity over a floor (x periodic, z walls,
// g = |g| (sin t, 0, -cos t)) against the analytic accelerations, a gas falling through an
// all-periodic box (relative motion untouched), the energy budget with unwrapped heights, and
// set_gravity() on live engines.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "hardsphere/collision_totals.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

constexpr double kRadius = 0.5, kLength = 10.0;

//! One sphere at rest on the floor (z = r, the contact plane) of a box periodic in x and y.
ParticleSystem sphere_on_floor() {
  ParticleSystem s;
  s.box = Box::from_lengths({kLength, kLength, kLength}, {true, true, false});
  s.push_back(1, 1, kRadius, 1.0, {2.0, 5.0, kRadius}, {0, 0, 0});
  return s;
}

Physics incline(double tilt) {
  Physics p;
  p.gravity = {std::sin(tilt), 0.0, -std::cos(tilt)};
  return p;
}

//! Rough spheres (Walton's law with sticking limit beta0 = 0) on a floor of friction mu.
Physics rough_incline(double tilt, double mu) {
  Physics p = incline(tilt);
  p.tangential_restitution = 0.0;
  p.friction = mu;
  return p;
}

//! The sphere's unwrapped x, velocity and spin after running `time`, from either engine.
struct Outcome {
  double x, vx, z, wy, energy_change, dissipated;
};

Vec3d unwrapped(const ParticleSystem& s, std::size_t i) {
  Vec3d x = s.pos[i];
  for (int d = 0; d < 3; ++d)
    if (s.box.periodic[std::size_t(d)]) x[d] += double(s.image[i][std::size_t(d)]) * s.box.length(d);
  return x;
}

double total_energy(const ParticleSystem& s, const Physics& p) {
  return kinetic_energy(s) + rotational_kinetic_energy(s, p.inertia) + potential_energy(s, p.gravity);
}

//! Energy the collisions took: rough spheres tally every collision by channel (walls included;
//! the wall_ fields are the walls' part), smooth ones the walls' losses only.
template <class Counters>
double dissipated(const Counters& c, const Physics& p) {
  const CollisionTotals t = collision_totals(c);
  if (p.rough()) return t.dissipated_normal + t.dissipated_tangential;
  return t.wall_dissipated_normal + t.wall_dissipated_tangential;
}

Outcome outcome(const ParticleSystem& start, const ParticleSystem& end, const Physics& p, double dissipation) {
  const Vec3d x = unwrapped(end, 0);
  return {x.x,
          end.vel[0].x,
          x.z,
          end.omega.empty() ? 0.0 : end.omega[0].y,
          total_energy(end, p) - total_energy(start, p),
          dissipation};
}

Outcome run_stepper(const ParticleSystem& s, const Physics& p, double dt, double time) {
  StepperConfig cfg;
  cfg.dt = dt;
  auto st = make_stepper(s, p, cfg);
  st->run(std::int64_t(std::llround(time / dt)));
  return outcome(s, st->state(), p, dissipated(st->counters(), p));
}

Outcome run_event(const ParticleSystem& s, const Physics& p, double time) {
  EventEngine e(s, p);
  e.advance(time);
  return outcome(s, e.state(), p, dissipated(e.counters(), p));
}

// The event engine's resting hop under |g| = 1 for unit diameter: kRestingTimeFraction sqrt(d / g).
const double kEventHop = kRestingTimeFraction;

}  // namespace

// A smooth sphere on a frictionless floor: the floor's impulses are along z only, so x follows
// the free parabola x0 + g sin(t) T^2 / 2 exactly (rounding: 1e-9 over T = 10, x ~ 24, two box
// lengths unwrapped), and z stays within a hop of the floor: a resting contact leaves at
// g cos(t) tau / 2 and lands tau later, rising g cos(t) tau^2 / 8 at most.
TEST(Chute, SmoothSphereOnAFrictionlessInclineAcceleratesAtGSinTheta) {
  const double tilt = 0.5, time = 10.0, dt = 0.01;
  const ParticleSystem s = sphere_on_floor();
  const Physics p = incline(tilt);
  EXPECT_NE(unbounded_flow(p, s.box.periodic).find("no frictional wall"), std::string::npos);
  const double a = std::sin(tilt);
  for (const auto& [name, out, hop] : {std::tuple{"stepper", run_stepper(s, p, dt, time), dt},
                                       std::tuple{"event", run_event(s, p, time), kEventHop}}) {
    SCOPED_TRACE(name);
    EXPECT_NEAR(out.x, 2.0 + 0.5 * a * time * time, 1e-9);
    EXPECT_NEAR(out.vx, a * time, 1e-9);
    EXPECT_GE(out.z, kRadius - 1e-12);
    EXPECT_LE(out.z, kRadius + std::cos(tilt) * hop * hop / 8 + 1e-12);
    // The budget with unwrapped heights: kinetic + potential change = -dissipation (the rests'
    // normal losses), to rounding of the energies (~12 here).
    EXPECT_NEAR(out.energy_change, -out.dissipated, 1e-9);
  }
}

// A rough sphere (Walton, beta0 = 0, q = 2/5) on a floor of friction mu = 0.1, tilted by t with
// tan t = 0.546 above mu (1 + q) / q = 0.35: it slides. Each resting contact (one per hop tau:
// the stepper's step, the event engine's resting time) takes the normal impulse g cos(t) tau
// and, sliding, the tangential mu g cos(t) tau, so after k hops v_x = k tau g (sin t - mu cos t)
// exactly; between contacts gravity adds g sin(t) up to one hop: |v_x - a T| <= g sin(t) tau
// and |x - x0 - a T^2 / 2| <= g sin(t) tau T. The spin takes mu g cos(t) / (q r) per unit time
// (within one hop's worth).
TEST(Chute, RoughSphereSlidesAtGSinMinusMuCosAboveTheRollingLimit) {
  const double tilt = 0.5, mu = 0.1, q = 0.4, time = 10.0, dt = 0.01;
  ASSERT_GT(std::tan(tilt), mu * (1 + q) / q);
  const ParticleSystem s = sphere_on_floor();
  Physics p = rough_incline(tilt, mu);
  EXPECT_EQ(unbounded_flow(p, s.box.periodic), "");  // a frictional floor and dissipation: it can settle
  const double a = std::sin(tilt) - mu * std::cos(tilt), spin = mu * std::cos(tilt) / (q * kRadius);
  for (const auto& [name, out, hop] : {std::tuple{"stepper", run_stepper(s, p, dt, time), dt},
                                       std::tuple{"event", run_event(s, p, time), kEventHop}}) {
    SCOPED_TRACE(name);
    const double dv = std::sin(tilt) * hop + 1e-9;
    EXPECT_NEAR(out.vx, a * time, dv);
    EXPECT_NEAR(out.x, 2.0 + 0.5 * a * time * time, dv * time);
    EXPECT_NEAR(std::abs(out.wy), spin * time, spin * hop + 1e-9);
    EXPECT_NEAR(out.energy_change, -out.dissipated, 1e-9);
  }
}

// Below that limit (t = 0.2: tan t = 0.203 < 0.35) the model rolls: with beta0 = 0 each contact
// stops the contact point, which gravity has moved at g sin(t) tau since the last, by the
// tangential impulse q / (1 + q) of it (below mu times the normal one: it sticks), so v_x gains
// g sin(t) tau / (1 + q) per hop: rolling, a = g sin t / (1 + q), as a rolling ball's. Between
// contacts gravity adds up to g sin(t) tau q / (1 + q): |v_x - a T| <= g sin(t) tau; the contact
// point moves at v_x - r w_y, below g sin(t) tau too.
TEST(Chute, RoughSphereRollsAtGSinOverOnePlusQBelowTheRollingLimit) {
  const double tilt = 0.2, mu = 0.1, q = 0.4, time = 10.0, dt = 0.01;
  ASSERT_LT(std::tan(tilt), mu * (1 + q) / q);
  const ParticleSystem s = sphere_on_floor();
  const Physics p = rough_incline(tilt, mu);
  const double a = std::sin(tilt) / (1 + q);
  for (const auto& [name, out, hop] : {std::tuple{"stepper", run_stepper(s, p, dt, time), dt},
                                       std::tuple{"event", run_event(s, p, time), kEventHop}}) {
    SCOPED_TRACE(name);
    const double dv = std::sin(tilt) * hop + 1e-9;
    EXPECT_NEAR(out.vx, a * time, dv);
    EXPECT_NEAR(out.x, 2.0 + 0.5 * a * time * time, dv * time);
    EXPECT_LT(std::abs(out.vx - kRadius * std::abs(out.wy)), dv);
    EXPECT_NEAR(out.energy_change, -out.dissipated, 1e-9);
  }
}

// Gravity along every axis of an all-periodic box: every sphere falls alike, so momentum grows as
// N m g T while the pairs' relative motion (and so the kinetic energy about the centre of mass of
// an elastic gas) is untouched; the stepper splits its steps as the speeds grow (phi 0.2, the
// gas reaches speed 20 along x, |g| T = 20.6) and ends without overlaps.
TEST(Chute, GasFallingThroughAPeriodicBoxKeepsItsRelativeMotion) {
  const ParticleSystem s = test::gas(300, 0.2, 5);
  Physics p;
  p.gravity = {1.0, 0.0, -0.25};
  EXPECT_NE(unbounded_flow(p, s.box.periodic).find("along periodic axis x"), std::string::npos);
  const double time = 20.0, n = double(s.size());
  const double internal0 = 1.5 * n * translational_temperature(s);
  StepperConfig cfg;
  cfg.dt = 0.05;
  auto st = make_stepper(s, p, cfg);
  st->run(400);
  EventEngine e(s, p);
  e.advance(time);
  for (const auto& [name, end] : {std::pair{"stepper", st->state()}, std::pair{"event", e.state()}}) {
    SCOPED_TRACE(name);
    const Vec3d mom = total_momentum(end);
    EXPECT_NEAR(mom.x / (n * time), 1.0, 1e-9);
    EXPECT_NEAR(mom.z / (n * time), -0.25, 1e-9);
    EXPECT_NEAR(1.5 * n * translational_temperature(end) / internal0, 1.0, 1e-9);
    EXPECT_LT(max_overlap(end), 1e-9);
  }
  EXPECT_GT(st->counters().substeps, 400);  // split as the gas sped up
}

// Gravity changed between steps: each step's flights are parabolas of the gravity it started
// with, so a free sphere's velocity is the sum of g_k dt_k and its unwrapped position the sum of
// the parabolas, in both engines, to rounding.
TEST(Chute, GravityChangedBetweenStepsGivesPiecewiseParabolas) {
  ParticleSystem s;
  s.box = Box::from_lengths({kLength, kLength, kLength}, {true, true, true});
  s.push_back(1, 1, kRadius, 1.0, {1.0, 2.0, 3.0}, {0.5, 0, 0});
  const std::array<double, 3> g1{0.0, 0.0, -1.0}, g2{0.6, 0.0, 0.8};
  // Stage 1: T1 = 2 under g1; stage 2: T2 = 3 under g2.
  const Vec3d v1{0.5, 0, -2.0}, x1{1.0 + 1.0, 2.0, 3.0 - 2.0};
  const Vec3d v2{0.5 + 1.8, 0, -2.0 + 2.4};
  const Vec3d x2{x1.x + v1.x * 3 + 0.5 * 0.6 * 9, 2.0, x1.z + v1.z * 3 + 0.5 * 0.8 * 9};
  StepperConfig cfg;
  cfg.dt = 0.01;
  Physics p;
  p.gravity = g1;
  auto st = make_stepper(s, p, cfg);
  st->run(200);
  st->set_gravity(g2);
  EXPECT_EQ(st->gravity(), g2);
  st->run(300);
  EventEngine e(s, p);
  e.advance(2.0);
  e.set_gravity(g2);
  EXPECT_EQ(e.gravity(), g2);
  e.advance(3.0);
  for (const auto& [name, end] : {std::pair{"stepper", st->state()}, std::pair{"event", e.state()}}) {
    SCOPED_TRACE(name);
    const Vec3d x = unwrapped(end, 0);
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(end.vel[0][d], v2[d], 1e-12);
      EXPECT_NEAR(x[d], x2[d], 1e-11);
    }
  }
}

// A sphere on a floor whose gravity turns (a drum's, sped up): the stepper and the event engine
// take the same sequence of accelerations, one per step, and end at the same place (both resolve
// the frictionless floor's resting contacts exactly; x differs by the hops' rounding only).
TEST(Chute, RotatingGravityOverAFloorInBothEngines) {
  const ParticleSystem s = sphere_on_floor();
  const double dt = 0.01;
  const auto g_at = [](int k) {
    const double t = 0.4 * std::sin(0.01 * k);
    return std::array<double, 3>{std::sin(t), 0.0, -std::cos(t)};
  };
  Physics p;
  p.gravity = g_at(0);
  StepperConfig cfg;
  cfg.dt = dt;
  auto st = make_stepper(s, p, cfg);
  EventEngine e(s, p);
  double vx = 0;
  for (int k = 0; k < 300; ++k) {
    st->set_gravity(g_at(k));
    e.set_gravity(g_at(k));
    st->run(1);
    e.advance(dt);
    vx += g_at(k)[0] * dt;
  }
  const ParticleSystem a = st->state(), b = e.state();
  EXPECT_NEAR(a.vel[0].x, vx, 1e-12);
  EXPECT_NEAR(b.vel[0].x, vx, 1e-12);
  EXPECT_NEAR(unwrapped(a, 0).x, unwrapped(b, 0).x, 1e-12);
}

TEST(Chute, SetGravityRefusesNonFiniteValuesNamingThem) {
  const ParticleSystem s = sphere_on_floor();
  StepperConfig cfg;
  cfg.names.gravity = "--gravity";
  auto st = make_stepper(s, {}, cfg);
  try {
    st->set_gravity({0, std::nan(""), -1});
    FAIL() << "not refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--gravity component y = nan must be finite"), std::string::npos) << e.what();
  }
  EventConfig ecfg;
  ecfg.names.gravity = "fix gravity";
  EventEngine e(s, {}, ecfg);
  EXPECT_THROW(e.set_gravity({std::numeric_limits<double>::infinity(), 0, 0}), InputError);
  // Rounding-level components are zero, as validated() makes them.
  st->set_gravity({1e-17, 0, -1});
  EXPECT_EQ(st->gravity()[0], 0.0);
}
