// When the stepper rebuilds its pair list: the pairwise guard on hand-made displacements (a
// mover against its threats, the caps of the spheres near it, the limits), and the stepper with
// the guard against the exact event engine on scenes built to have many movers.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"
#include "stepper/list_guard.hpp"

using namespace hardsphere;
using Guard = detail::ListGuard<double>;

namespace {

constexpr double kSkin = 1.0;

//! Threats of each sphere as (j, gap): sphere 0 and 1 are 1.2 skins apart, 0 and 2 are 1.0.
struct Threats {
  std::vector<std::vector<std::pair<std::uint32_t, double>>> of{{{1, 1.2}, {2, 1.0}}, {{0, 1.2}}, {{0, 1.0}}, {}};
  int calls = 0;
  auto fn() {
    return [this](std::uint32_t i, auto&& push) {
      ++calls;
      for (const auto& [j, gap] : of[i]) push(j, gap);
    };
  }
};

//! A guard over 4 spheres with a skin of 1, nothing moved yet.
Guard fresh_guard(bool pairwise = true, std::size_t max_movers = 16) {
  Guard g;
  g.configure(kSkin, pairwise, max_movers);
  g.reset(4);
  return g;
}

//! Sets sphere displacements d (in skins) and asks the guard after a drift.
bool after_drift(Guard& g, Threats& t, const std::vector<double>& d) {
  double m = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    g.displacements()[i] = std::max(g.displacements()[i], d[i] * d[i]);
    m = std::max(m, g.displacements()[i]);
  }
  // The engines' form, told which spheres are past skin / 2, must agree with the full scan.
  Guard told = g;
  std::vector<std::uint32_t> past;
  for (std::uint32_t i = 0; i < d.size(); ++i)
    if (told.displacements()[i] >= told.candidate_d2()) past.push_back(i);
  Threats t_told = t;  // its own call count
  const bool valid_told = told.valid_after_drift(m, past.data(), past.size(), t_told.fn());
  const bool valid = g.valid_after_drift(m, t.fn());
  EXPECT_EQ(valid_told, valid);
  EXPECT_EQ(told.movers(), g.movers());
  return valid;
}

}  // namespace

TEST(ListGuard, ClassicTestExpiresAtHalfTheSkin) {
  Guard g = fresh_guard(false);
  Threats t;
  EXPECT_TRUE(after_drift(g, t, {0.49, 0.1, 0.2, 0.3}));
  EXPECT_FALSE(after_drift(g, t, {0.5, 0.1, 0.2, 0.3}));
  EXPECT_EQ(t.calls, 0);
}

TEST(ListGuard, MoverStaysValidUntilAThreatsGapIsClosed) {
  Guard g = fresh_guard();
  Threats t;
  // Sphere 0 is past half the skin; 2 (gap 1.0) has room 0.3, 1 (gap 1.2) room 0.5.
  EXPECT_TRUE(after_drift(g, t, {0.7, 0.45, 0.29, 0.49}));
  EXPECT_EQ(g.movers(), 1u);
  EXPECT_EQ(t.calls, 1);
  // Inside a step sphere 2 moves on: within its cap, then past it.
  g.note(2, 0.295 * 0.295, t.fn());
  EXPECT_FALSE(g.expired());
  g.note(2, 0.31 * 0.31, t.fn());
  EXPECT_TRUE(g.expired());
}

TEST(ListGuard, TwoMoversCheckTheirSumAndAMoverItsNewDisplacement) {
  Guard g = fresh_guard();
  Threats t;
  EXPECT_TRUE(after_drift(g, t, {0.6, 0.55, 0.1, 0.4}));  // 0.6 + 0.55 < 1.2
  EXPECT_EQ(g.movers(), 2u);
  g.note(0, 0.64 * 0.64, t.fn());  // 0.64 + 0.55 < 1.2; and 0.64 + 0.1 < 1.0
  EXPECT_FALSE(g.expired());
  g.note(0, 0.66 * 0.66, t.fn());  // 0.66 + 0.55 > 1.2
  EXPECT_TRUE(g.expired());
  g.reset(4);  // a rebuild: nothing has moved
  EXPECT_FALSE(g.expired());
  EXPECT_EQ(g.movers(), 0u);
}

TEST(ListGuard, AThreatThatBecomesAMoverIsChecked) {
  Guard g = fresh_guard();
  Threats t;
  EXPECT_TRUE(after_drift(g, t, {0.69, 0.2, 0.1, 0.1}));
  g.note(1, 0.52 * 0.52, t.fn());  // 1 becomes a mover: 0.69 + 0.52 > 1.2
  EXPECT_TRUE(g.expired());
}

TEST(ListGuard, LimitsOnTheLargestMoveAndOnTheNumberOfMovers) {
  Guard g = fresh_guard();
  Threats t;
  t.of = {{}, {}, {}, {}};  // nothing near: only the limits can expire the list
  EXPECT_TRUE(after_drift(g, t, {0.84, 0.6, 0.1, 0.1}));
  EXPECT_FALSE(after_drift(g, t, {0.86, 0.6, 0.1, 0.1}));  // beyond kMaxMove = 0.85 skins
  Guard few = fresh_guard(true, 1);
  EXPECT_TRUE(after_drift(few, t, {0.6, 0.1, 0.1, 0.1}));
  EXPECT_FALSE(after_drift(few, t, {0.6, 0.6, 0.1, 0.1}));  // a second mover: a rebuild is due
}

namespace {

//! A dense gas in which every 20th sphere is five times as fast: movers appear within a few
//! steps, and their threats decide when the list expires.
ParticleSystem gas_with_fast_spheres(std::int64_t n, double phi, std::uint64_t seed) {
  auto s = test::gas(n, phi, seed);
  for (std::size_t i = 0; i < s.size(); i += 20) s.vel[i] = 5.0 * s.vel[i];
  return s;
}

double worst_distance(const ParticleSystem& a, const ParticleSystem& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    Vec3d d = a.pos[i] - b.pos[i];
    for (int k = 0; k < 3; ++k)
      if (a.box.periodic[k]) d[k] -= a.box.length(k) * std::nearbyint(d[k] / a.box.length(k));
    worst = std::max(worst, norm(d));
  }
  return worst;
}

//! The stepper with and without the pairwise guard against the event engine: the same
//! collisions and final state (a list that expired too late would lose collisions).
void expect_exact_with_fewer_rebuilds(const ParticleSystem& s, double dt, std::int64_t steps) {
  EventEngine e(s);
  e.advance(dt * double(steps));
  StepperConfig pairwise, classic;
  pairwise.dt = classic.dt = dt;
  pairwise.detect = classic.detect = Detect::Sweep;  // grazes too, as the event engine
  classic.pairwise_list_check = false;
  auto a = make_stepper(s, {}, pairwise), b = make_stepper(s, {}, classic);
  a->run(steps);
  b->run(steps);
  EXPECT_GT(e.counters().collisions, std::int64_t(2 * s.size()));
  EXPECT_EQ(a->counters().collisions, e.counters().collisions);
  EXPECT_EQ(b->counters().collisions, e.counters().collisions);
  EXPECT_EQ(a->counters().wall_collisions, e.counters().wall_collisions);
  EXPECT_LT(worst_distance(a->state(), e.state()), 1e-8);
  EXPECT_LT(worst_distance(b->state(), e.state()), 1e-8);
  // The guard let the list live longer, or this scene did not test it.
  EXPECT_LT(double(a->counters().rebuilds), 0.8 * double(b->counters().rebuilds))
      << a->counters().rebuilds << " against " << b->counters().rebuilds;
}

}  // namespace

TEST(StepperListGuard, FastSpheresInADenseGasLoseNoCollision) {
  expect_exact_with_fewer_rebuilds(gas_with_fast_spheres(2000, 0.35, 4), 0.004, 60);
}

TEST(StepperListGuard, PolydisperseMixtureWithWallsLosesNoCollision) {
  auto s = test::binary_mixture_with_walls(300);
  for (std::size_t i = 0; i < s.size(); i += 10) s.vel[i] = 4.0 * s.vel[i];
  expect_exact_with_fewer_rebuilds(s, 0.005, 200);
}

TEST(StepperListGuard, NoUnlistedPairEverOverlaps) {
  // A missed contact leaves an overlapping pair at the end of a step. Many list lifetimes of a
  // Maxwell-Boltzmann gas, whose fastest spheres are the movers: no step may end with one.
  const auto s = test::gas(3000, 0.3, 21);
  StepperConfig cfg;
  cfg.dt = 0.02;
  auto st = make_stepper(s, {}, cfg);
  double worst = 0;
  for (int step = 0; step < 600; ++step) {
    st->run(1);
    worst = std::max(worst, max_overlap(st->state()));
  }
  EXPECT_GT(st->counters().rebuilds, 50);
  EXPECT_EQ(worst, 0.0);
}

TEST(StepperListGuard, LongStepsKeepTheListForWholeSteps) {
  // At dt = 1.2 mean free times (phi 0.3) the fastest spheres cross a dense-gas skin within one
  // step. The automatic skin must grow with the step: otherwise they expire the list in the
  // middle of steps, and each rebuild re-scans every pair (90 rebuilds per step were measured).
  // The run must still conserve energy and end without an overlapping pair.
  const auto s = test::gas(3000, 0.3, 5);
  StepperConfig cfg;
  cfg.dt = 0.12;
  auto st = make_stepper(s, {}, cfg);
  const double e0 = kinetic_energy(s);
  const std::int64_t steps = 20;
  st->run(steps);
  EXPECT_GT(st->counters().collisions, std::int64_t(s.size()));
  EXPECT_LE(st->counters().rebuilds, steps) << "the list expired within steps";
  EXPECT_NEAR(kinetic_energy(st->state()) / e0, 1.0, 1e-12);
  EXPECT_EQ(max_overlap(st->state()), 0.0);
}
