// The stepper as a whole: analytic few-body runs, conservation laws, Maxwell-Boltzmann
// relaxation, invariance under the cell grid, determinism, and the dense initial route.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <tuple>
#include <utility>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/state_exchange.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

using test::binary_mixture_with_walls;
using test::gas;
using test::two;

ParticleSystem run(const ParticleSystem& sys, double dt, std::int64_t steps, StepperConfig cfg = {},
                   Precision p = Precision::Double, StepCounters* counters = nullptr) {
  cfg.dt = dt;
  auto st = make_stepper(sys, {}, cfg, p);
  st->run(steps);
  if (counters) *counters = st->counters();
  return st->state();
}

}  // namespace

TEST(StepperTwoBody, HeadOnPairIsRewoundToExactContact) {
  // Gap 1 closing at speed 2: contact at t = 0.5, inside the second step of 0.3. After the
  // rewind, swap and re-advance by 0.1 the spheres sit 0.1 back from where they touched.
  const auto s = two({2, 5, 5}, {1, 0, 0}, {4, 5, 5}, {-1, 0, 0});
  StepCounters c;
  const auto out = run(s, 0.3, 2, StepperConfig{}, Precision::Double, &c);
  EXPECT_EQ(c.collisions, 1);
  EXPECT_NEAR(out.pos[0].x, 2.4, 1e-12);
  EXPECT_NEAR(out.pos[1].x, 3.6, 1e-12);
  EXPECT_DOUBLE_EQ(out.vel[0].x, -1.0);
  EXPECT_DOUBLE_EQ(out.vel[1].x, 1.0);
  // Virial r_ij . dp_i = |r| * J = 1 * 2 for unit masses, all of it in the xx component.
  EXPECT_NEAR(c.pair_virial, 2.0, 1e-12);
  EXPECT_NEAR(c.pair_virial_tensor[0], 2.0, 1e-12);
  for (int k = 1; k < 6; ++k) EXPECT_NEAR(c.pair_virial_tensor[k], 0.0, 1e-15) << "component " << k;
}

TEST(StepperTwoBody, ObliqueImpactVirialTensor) {
  // Contact normal (1, 1, 0)/sqrt(2) at unit distance, sphere 1 moving along +x into sphere 2
  // at rest: J = |dv.n| = 1/sqrt(2) along n, so r (x) dp = J n (x) n with n (x) n = 1/2 in
  // xx, yy and xy: each component 1/(2 sqrt(2)), trace = r.dp = J.
  const double h = 1 / std::sqrt(2.0);
  // Sphere 1 reaches the contact point 0.05 into a step of 0.2.
  const auto s = two({5 - 0.5 * h - 0.05, 5 - 0.5 * h, 5}, {1, 0, 0}, {5 + 0.5 * h, 5 + 0.5 * h, 5}, {0, 0, 0});
  StepCounters c;
  run(s, 0.2, 1, StepperConfig{}, Precision::Double, &c);
  ASSERT_EQ(c.collisions, 1);
  const double q = 0.5 * h;
  EXPECT_NEAR(c.pair_virial_tensor[0], q, 1e-12);
  EXPECT_NEAR(c.pair_virial_tensor[1], q, 1e-12);
  EXPECT_NEAR(c.pair_virial_tensor[3], q, 1e-12);
  EXPECT_NEAR(c.pair_virial_tensor[2], 0.0, 1e-15);
  EXPECT_NEAR(c.pair_virial, h, 1e-12);
}

TEST(StepperTwoBody, PairAcrossThePeriodicBoundaryCollides) {
  // Same collision through the x faces: the minimum image is used.
  const auto s = two({0.5, 5, 5}, {-1, 0, 0}, {8.5, 5, 5}, {1, 0, 0});
  StepCounters c;
  const auto out = run(s, 0.3, 2, StepperConfig{}, Precision::Double, &c);
  EXPECT_EQ(c.collisions, 1);
  EXPECT_NEAR(out.pos[0].x, 0.1, 1e-12);
  EXPECT_NEAR(out.pos[1].x, 8.9, 1e-12);
  EXPECT_DOUBLE_EQ(out.vel[0].x, 1.0);
}

TEST(Stepper, AutoDetectionFollowsSpeedsThatGrow) {
  // A 50/50 mixture of masses 1 and 1e6 at equal speeds heads for equipartition: the light
  // spheres speed up ~1000x. Auto starts in overlap mode (v_rms dt = 0.01 diameters) and must
  // switch to sweeping once v_rms dt passes 0.1; it kept overlap for the whole run before.
  ParticleSystem s;
  const int k = 10;
  const double a = std::cbrt(M_PI / 6 / 0.2);  // lattice spacing for phi 0.2
  s.box = Box::from_lengths({k * a, k * a, k * a}, {true, true, true});
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0, 1);
  for (int i = 0; i < k * k * k; ++i) {
    Vec3d v{g(rng), g(rng), g(rng)};
    v = (1 / norm(v)) * v;
    s.push_back(i + 1, 1, 0.5, i % 2 ? 1e6 : 1.0, {(i % k + 0.5) * a, (i / k % k + 0.5) * a, (i / k / k + 0.5) * a}, v);
  }
  StepperConfig cfg;
  auto st = make_stepper(s, {}, cfg);
  EXPECT_FALSE(st->sweep_detection());
  st->run(1500);
  EXPECT_TRUE(st->sweep_detection());
  EXPECT_LT(max_overlap(st->state()), 1e-9);
}

TEST(StepperTwoBody, WallBounceMirrorsAtTheContactTime) {
  // Radius 0.5 at x = 1 moving at -1 toward the wall at 0: contact after 0.5, then 0.2 back.
  auto s = two({1, 5, 5}, {-1, 0, 0}, {7, 5, 5}, {0, 0, 0}, 0.5, 0.5, 1, 1, 10, {false, true, true});
  StepCounters c;
  const auto out = run(s, 0.7, 1, StepperConfig{}, Precision::Double, &c);
  EXPECT_EQ(c.wall_collisions, 1);
  EXPECT_NEAR(out.pos[0].x, 0.7, 1e-12);
  EXPECT_DOUBLE_EQ(out.vel[0].x, 1.0);
  EXPECT_NEAR(c.wall_impulse[0], 2.0, 1e-12);
}

TEST(StepperTwoBody, ChainIsResolvedInTimeOrder) {
  // A hits B (at rest) at t = 0.5; B then hits C (at rest, 0.5 gap) at t = 1.0, all in one
  // step of 1.2: the momentum must end on C, not be lost to an out-of-order resolution.
  ParticleSystem s;
  s.box = Box::from_lengths({20, 20, 20}, {true, true, true});
  s.push_back(1, 1, 0.5, 1.0, {2, 5, 5}, {1, 0, 0});
  s.push_back(2, 1, 0.5, 1.0, {3.5, 5, 5}, {0, 0, 0});
  s.push_back(3, 1, 0.5, 1.0, {5.0, 5, 5}, {0, 0, 0});
  StepCounters c;
  const auto out = run(s, 1.2, 1, StepperConfig{}, Precision::Double, &c);
  EXPECT_EQ(c.collisions, 2);
  EXPECT_NEAR(out.vel[0].x, 0.0, 1e-15);
  EXPECT_NEAR(out.vel[1].x, 0.0, 1e-15);
  EXPECT_NEAR(out.vel[2].x, 1.0, 1e-15);
  EXPECT_NEAR(out.pos[0].x, 2.5, 1e-12);
  EXPECT_NEAR(out.pos[1].x, 4.0, 1e-12);
  EXPECT_NEAR(out.pos[2].x, 5.2, 1e-12);
}

TEST(StepperTwoBody, WallBouncesTakeTheirTurnWithContacts) {
  // Two scenes by the x wall at 10 (contact plane x = 9.5), one step of 0.5, against the exact
  // event engine. (1) A (speed 4) hits B at t = 0.025; B, sent to the wall, touches C at
  // t = 0.266 on its way there. (2) D heads for the wall and touches E (by the wall) at
  // t = 0.182 first. Mirroring B or D at the wall before sweeping the path to it missed the
  // contact with C or E and left them overlapping. One cell in a box 20 long on the periodic
  // axes gives a skin of 9, so the step of 0.5 (paths of 2) is not split into sub-steps.
  ParticleSystem s;
  s.box = Box::from_lengths({10, 20, 20}, {false, true, true});
  s.push_back(1, 1, 0.5, 1.0, {6.9, 2, 5}, {4, 0, 0});    // A
  s.push_back(2, 1, 0.5, 1.0, {8.0, 2, 5}, {0, 0, 0});    // B
  s.push_back(3, 1, 0.5, 1.0, {9.4, 2.9, 5}, {0, 0, 0});  // C
  s.push_back(4, 1, 0.5, 1.0, {8.6, 7, 5}, {2, 0, 0});    // D
  s.push_back(5, 1, 0.5, 1.0, {9.4, 7.9, 5}, {0, 0, 0});  // E
  EventEngine exact(s);
  exact.advance(0.5);
  const auto want = exact.state();
  ASSERT_EQ(exact.counters().collisions, 3);
  for (const Detect detect : {Detect::Overlap, Detect::Sweep}) {
    StepperConfig cfg;
    cfg.detect = detect;
    cfg.cells = {1, 1, 1};
    StepCounters c;
    const auto out = run(s, 0.5, 1, cfg, Precision::Double, &c);
    EXPECT_EQ(c.substeps, 1);
    EXPECT_EQ(c.collisions, 3);
    EXPECT_EQ(c.wall_collisions, exact.counters().wall_collisions);
    EXPECT_EQ(max_overlap(out), 0.0);
    for (std::size_t i = 0; i < s.size(); ++i) {
      EXPECT_LT(norm(out.pos[i] - want.pos[i]), 1e-12) << "sphere " << i + 1;
      EXPECT_LT(norm(out.vel[i] - want.vel[i]), 1e-12) << "sphere " << i + 1;
    }
  }
}

TEST(StepperConservation, GasOf1000Over10000Steps) {
  // 10^3 spheres at phi = 0.3, 10^4 steps: every collision conserves momentum exactly for
  // equal masses (antisymmetric update), energy to round-off per collision.
  const auto s = gas(1000, 0.3, 7);
  StepCounters c;
  const auto out = run(s, 0.01, 10000, StepperConfig{}, Precision::Double, &c);
  EXPECT_GT(c.collisions, 300000);
  const double e0 = kinetic_energy(s), e1 = kinetic_energy(out);
  EXPECT_LT(std::abs(e1 - e0) / e0, 1e-12);
  const Vec3d p = total_momentum(out);
  EXPECT_LT(norm(p), 1e-10);  // |p| of the gas is ~30; round-off of ~1e6 antisymmetric updates
  EXPECT_EQ(max_overlap(out), 0.0);
  EXPECT_EQ(c.unresolved_steps, 0);
}

TEST(StepperConservation, PolydisperseMixtureWithWalls) {
  // Two sizes and masses, walls on z: momentum along x, y conserved, energy to round-off.
  const auto s = test::binary_mixture_with_walls(300);
  StepCounters c;
  const auto out = run(s, 0.01, 3000, StepperConfig{}, Precision::Double, &c);
  EXPECT_GT(c.collisions, 5000);
  EXPECT_GT(c.wall_collisions, 500);
  const double e0 = kinetic_energy(s), e1 = kinetic_energy(out);
  EXPECT_LT(std::abs(e1 - e0) / e0, 1e-12);
  const Vec3d p0 = total_momentum(s), p1 = total_momentum(out);
  EXPECT_NEAR(p1.x, p0.x, 1e-11);
  EXPECT_NEAR(p1.y, p0.y, 1e-11);
  EXPECT_EQ(max_overlap(out), 0.0);
}

TEST(StepperEventLimit, StepsCutShortStillKeepSpheresInsideTheWalls) {
  // One event per step: most contacts are left unresolved (counted), but every sphere that
  // ended a step beyond a wall is still mirrored back, and energy is still conserved.
  const auto s = test::binary_mixture_with_walls(300);
  StepperConfig cfg;
  cfg.max_events_per_step = 1;
  StepCounters c;
  const auto out = run(s, 0.02, 200, cfg, Precision::Double, &c);
  EXPECT_GT(c.unresolved_steps, 100);
  EXPECT_GT(c.wall_collisions, 100);
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_GE(out.pos[i].z, out.box.lo[2] + out.radius[i]) << "sphere " << i;
    EXPECT_LE(out.pos[i].z, out.box.hi[2] - out.radius[i]) << "sphere " << i;
  }
  EXPECT_LT(std::abs(kinetic_energy(out) - kinetic_energy(s)) / kinetic_energy(s), 1e-12);
}

TEST(StepperConservation, SweepDetectionAndFloatPrecision) {
  const auto s = gas(1000, 0.25, 11);
  StepperConfig sweep;
  sweep.detect = Detect::Sweep;
  StepCounters cs, cf;
  const auto out_s = run(s, 0.02, 1000, sweep, Precision::Double, &cs);
  EXPECT_LT(std::abs(kinetic_energy(out_s) / kinetic_energy(s) - 1), 1e-12);
  EXPECT_EQ(max_overlap(out_s), 0.0);
  const auto out_f = run(s, 0.02, 1000, StepperConfig{}, Precision::Float, &cf);
  EXPECT_LT(std::abs(kinetic_energy(out_f) / kinetic_energy(s) - 1), 1e-4);  // float round-off
  EXPECT_LT(max_overlap(out_f), 1e-5);
  // Same physics: collision totals agree within their statistical spread. Over 12 seeds the ratio
  // has mean 1.0015 and sd 0.47%; 3% is over 6 sd. The float drift spread by 3.5e-8.
  EXPECT_NEAR(double(cf.collisions) / double(cs.collisions), 1.0, 0.03);
}

TEST(StepperMaxwell, OneSpeedGasRelaxesToMaxwellBoltzmann) {
  // All 4000 spheres start at |v| = sqrt(3) (T = 1): the speed distribution is far from MB.
  // After ~25 collisions per sphere it must pass a Kolmogorov-Smirnov test against MB at
  // T = <m v^2>/3: p above 6e-5, the two-sided 4-sigma tail (over 12 seeds p was 0.32 to 1.0).
  const auto s = gas(4000, 0.3, 5, std::sqrt(3.0));
  const double t0 = temperature(s);
  EXPECT_LT(kolmogorov_pvalue(maxwell_ks_distance(s, t0), s.size()), 1e-10);  // the test can fail
  const auto out = run(s, 0.01, 300);
  const double t = temperature(out);
  EXPECT_NEAR(t, t0, 1e-12);
  const double p = kolmogorov_pvalue(maxwell_ks_distance(out, t), out.size());
  EXPECT_GT(p, 6e-5) << "KS distance " << maxwell_ks_distance(out, t);
}

TEST(StepperCells, OneBoxAndAutoCellsGiveTheSameCollisions) {
  // K = 1 is the seed's all-pairs baseline; auto and a fixed 3^3 grid must resolve the very
  // same collisions, with states equal to round-off. The grids differ only in how a periodic
  // image is subtracted (last-bit differences), which the gas's chaos amplifies by ~e^(4t):
  // over t = 1 that stays far below the 1e-9 tolerance, over t = 4 it would not.
  const auto s = gas(300, 0.2, 9);
  StepperConfig one, three;
  one.cells = {1, 1, 1};
  three.cells = {3, 3, 3};
  StepCounters ca, c1, c3;
  const auto a = run(s, 0.01, 100, StepperConfig{}, Precision::Double, &ca);
  const auto b = run(s, 0.01, 100, one, Precision::Double, &c1);
  const auto c = run(s, 0.01, 100, three, Precision::Double, &c3);
  ASSERT_GT(ca.collisions, 300);
  EXPECT_EQ(ca.collisions, c1.collisions);
  EXPECT_EQ(ca.collisions, c3.collisions);
  for (std::size_t i = 0; i < s.size(); ++i) {
    EXPECT_NEAR(a.pos[i].x, b.pos[i].x, 1e-9);
    EXPECT_NEAR(a.vel[i].y, b.vel[i].y, 1e-9);
    EXPECT_NEAR(a.pos[i].z, c.pos[i].z, 1e-9);
  }
}

TEST(StepperDeterminism, SameSeedSameRunDifferentSeedDifferentRun) {
  const auto a = run(gas(500, 0.3, 42), 0.01, 200);
  const auto b = run(gas(500, 0.3, 42), 0.01, 200);
  const auto c = run(gas(500, 0.3, 43), 0.01, 200);
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a.pos[i].x, b.pos[i].x);
    ASSERT_EQ(a.vel[i].z, b.vel[i].z);
  }
  EXPECT_NE(a.pos[0].x, c.pos[0].x);
}

TEST(StepperPressure, CompressibilityFactorNearCarnahanStarling) {
  // phi = 0.3, dt = 0.005 (~0.04 mean free times): Z within 1.5% of CS. Over 12 seeds Z / Z_CS
  // had mean 1.0024 (CS and the small-dt bias of overlap detection) and sd 0.19%: |mean| + 4 sd
  // = 1.0%.
  const double phi = 0.3;
  auto s = gas(2000, phi, 21);
  StepperConfig cfg;
  cfg.dt = 0.005;
  auto st = make_stepper(s, {}, cfg);
  st->run(200);  // forget the initial state
  st->reset_counters();
  st->run(2000);
  const auto& c = st->counters();
  const double z = compressibility_factor(c.pair_virial, c.sim_time, s.size(), temperature(s));
  const double z_cs = (1 + phi + phi * phi - phi * phi * phi) / std::pow(1 - phi, 3);
  EXPECT_NEAR(z / z_cs, 1.0, 0.015) << "Z " << z << " vs CS " << z_cs;
}

TEST(StepperInput, RejectsBadTimeStepAndCells) {
  const auto s = gas(100, 0.1, 1);
  StepperConfig cfg;
  cfg.dt = 0;
  EXPECT_THROW(make_stepper(s, {}, cfg), InputError);
  cfg.dt = std::nan("");
  EXPECT_THROW(make_stepper(s, {}, cfg), InputError);
  cfg.dt = 0.01;
  cfg.cells = {50, 50, 50};  // cells narrower than a diameter
  EXPECT_THROW(make_stepper(s, {}, cfg), InputError);
}

TEST(DenseInit, LatticeRouteBetweenWalls) {
  // The lattice route's dynamics between walls: with wall bounces resolved out of time order,
  // 3 of these 5 seeds ended with an overlap (~1e-3) and the start was refused.
  for (const std::array<bool, 3> periodic : {std::array<bool, 3>{false, false, false}, {true, true, false}}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const auto s = gas(3000, 0.3, seed, std::nullopt, periodic);
      EXPECT_EQ(max_overlap(s), 0.0) << "seed " << seed;
    }
  }
}

TEST(DenseInit, LatticeRouteReachesHalfPacking) {
  const auto s = gas(500, 0.50, 4);
  EXPECT_NEAR(s.packing_fraction(), 0.50, 1e-12);
  EXPECT_EQ(max_overlap(s), 0.0);
  EXPECT_NEAR(norm(total_momentum(s)), 0.0, 1e-10);
  EXPECT_NEAR(temperature(s), 1.0, 1e-12);
}

TEST(StepperDetection, AutoSweepsOnlyStepsLongEnoughForGrazes) {
  // One speed (v_rms = 1 exactly), unit diameters: the threshold v_rms dt = 0.1 diameters.
  auto s = gas(100, 0.1, 3, 1.0);
  EXPECT_FALSE(detects_by_sweep(Detect::Auto, s, 0.099));
  EXPECT_TRUE(detects_by_sweep(Detect::Auto, s, 0.101));
  EXPECT_FALSE(detects_by_sweep(Detect::Overlap, s, 1.0));
  EXPECT_TRUE(detects_by_sweep(Detect::Sweep, s, 0.001));
  s.radius[7] = 0.25;  // the smallest sphere sets the scale
  EXPECT_TRUE(detects_by_sweep(Detect::Auto, s, 0.051));
  EXPECT_THROW(parse_detect("psychic"), InputError);
  EXPECT_EQ(parse_detect("auto"), Detect::Auto);
}

TEST(StepperDetection, DefaultIsOverlapForShortStepsAndSweepForLongOnes) {
  // The default configuration runs exactly the explicit mode that auto picks: the same
  // collisions and final state. At dt = 0.2 (phi 0.2, about one mean free time) that is sweep
  // detection, which sees the grazes and leaves no overlapping pair.
  const auto s = gas(1500, 0.2, 11);
  for (const auto& [dt, picked] : {std::pair{0.01, Detect::Overlap}, std::pair{0.2, Detect::Sweep}}) {
    StepperConfig by_default, explicit_mode;
    explicit_mode.detect = picked;
    StepCounters a, b;
    const auto out_a = run(s, dt, 20, by_default, Precision::Double, &a);
    const auto out_b = run(s, dt, 20, explicit_mode, Precision::Double, &b);
    EXPECT_GT(a.collisions, 100) << "dt " << dt;
    EXPECT_EQ(a.collisions, b.collisions) << "dt " << dt;
    for (std::size_t i = 0; i < s.size(); ++i)
      ASSERT_EQ(norm(out_a.pos[i] - out_b.pos[i]), 0.0) << "dt " << dt << " sphere " << i;
    EXPECT_EQ(max_overlap(out_a), 0.0) << "dt " << dt;
  }
}

TEST(StepperConfigHint, GasPackingFractionSetsTheAutoSkinOfAPaddedBox) {
  // One MPI rank's box holds its spheres and empty margins. Told the gas's packing fraction,
  // its stepper picks the skin a stepper over the whole gas picks (thinner at phi >= 0.3).
  const ParticleSystem dense = gas(4000, 0.3, 11);
  ParticleSystem padded = dense;
  padded.box.hi[0] += dense.box.length(0);  // half the box empty: phi 0.15 by volume
  padded.box.periodic[0] = false;
  StepperConfig cfg;
  cfg.dt = 0.01;
  const double whole = make_stepper(dense, {}, cfg)->skin(), box = make_stepper(padded, {}, cfg)->skin();
  cfg.packing_fraction = dense.packing_fraction();
  const double told = make_stepper(padded, {}, cfg)->skin();
  // Auto skins are 0.4 diameters at phi 0.3 and 0.6 at 0.15, widened to whole cells.
  EXPECT_GT(box, 0.55);
  EXPECT_LT(whole, 0.5);
  EXPECT_LT(told, 0.5);
  cfg.packing_fraction = 1.0;
  EXPECT_THROW(make_stepper(padded, {}, cfg), InputError);
  cfg.packing_fraction = -0.1;
  EXPECT_THROW(make_stepper(padded, {}, cfg), InputError);
}
