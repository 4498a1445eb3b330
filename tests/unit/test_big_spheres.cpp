// Big spheres in the stepper: the grid is sized without them and a pass of their own finds their
// pairs. Runs on the auto grid must resolve the very same collisions as the all-pairs baseline
// (cells 1,1,1, which sizes its one cell by the largest sphere), with states equal to round-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "hardsphere/errors.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/stepper.hpp"
#include "scene/size_classes.hpp"

using namespace hardsphere;

namespace {

struct Big {
  double diameter, mass;
  Vec3d pos;  // NaN coordinates: a random place
};

//! `n_small` spheres with diameters from `small_d` (mass d^3) placed by random sequential
//! addition around the given big spheres (ids first), velocities Maxwell-Boltzmann at T = 1.
ParticleSystem scene(const Box& box, const std::vector<Big>& bigs, std::size_t n_small,
                     double (*small_d)(std::mt19937_64&), std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  ParticleSystem s;
  s.box = box;
  auto clear = [&](const Vec3d& p, double r) {
    for (int d = 0; d < 3; ++d)
      if (!box.periodic[d] && (p[d] - r < box.lo[d] || p[d] + r > box.hi[d])) return false;
    for (std::size_t k = 0; k < s.size(); ++k) {
      Vec3d dr = p - s.pos[k];
      for (int d = 0; d < 3; ++d)
        if (box.periodic[d]) dr[d] -= box.length(d) * std::nearbyint(dr[d] / box.length(d));
      if (norm(dr) < r + s.radius[k]) return false;
    }
    return true;
  };
  auto place = [&](double diameter, double mass, Vec3d p) {
    const double r = diameter / 2;
    while (std::isnan(p.x) || !clear(p, r))
      for (int d = 0; d < 3; ++d) p[d] = box.lo[d] + r + u(rng) * (box.length(d) - 2 * r);
    const double v = 1 / std::sqrt(mass);
    s.push_back(std::int64_t(s.size() + 1), 1, r, mass, p, {v * g(rng), v * g(rng), v * g(rng)});
  };
  for (const Big& b : bigs) place(b.diameter, b.mass, b.pos);
  std::vector<double> d(n_small);
  for (double& x : d) x = small_d(rng);
  std::sort(d.begin(), d.end(), [](double a, double b) { return a > b; });
  const double nan = std::nan("");
  for (const double x : d) place(x, x * x * x, {nan, nan, nan});
  return s;
}

double unit(std::mt19937_64&) { return 1.0; }
double lognormal(std::mt19937_64& rng) { return std::lognormal_distribution<double>(0.0, 0.3)(rng); }

//! Runs the scene on the auto grid (or `cells`) and on one cell; both must agree collision by
//! collision. Returns the auto grid's cell counts.
std::array<int, 3> expect_same_as_all_pairs(const ParticleSystem& s, std::int64_t steps,
                                            std::array<int, 3> cells = {0, 0, 0}) {
  StepperConfig grid, one;
  grid.detect = one.detect = Detect::Sweep;  // exact contacts: sub-steps change nothing
  grid.cells = cells;
  one.cells = {1, 1, 1};
  auto a = make_stepper(s, {}, grid), b = make_stepper(s, {}, one);
  a->run(steps);
  b->run(steps);
  EXPECT_GT(a->counters().collisions, 100);
  EXPECT_EQ(a->counters().collisions, b->counters().collisions);
  EXPECT_EQ(a->counters().wall_collisions, b->counters().wall_collisions);
  const auto x = a->state(), y = b->state();
  double worst = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    Vec3d dr = x.pos[i] - y.pos[i];
    for (int d = 0; d < 3; ++d)
      if (s.box.periodic[d]) dr[d] -= s.box.length(d) * std::nearbyint(dr[d] / s.box.length(d));
    worst = std::max({worst, norm(dr), norm(x.vel[i] - y.vel[i])});
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(max_overlap(x), 1e-9);
  return a->cells_per_dim();
}

Box cube(double l, std::array<bool, 3> periodic) { return Box::from_lengths({l, l, l}, periodic); }

}  // namespace

TEST(StepperBigSpheres, OneBigSphereOfRatio10MatchesAllPairs) {
  // D = 10, M = 10^3 among 2500 unit spheres (phi ~0.17 with it); the auto grid's cells are
  // about two small diameters wide, so the big sphere's pairs come from its own pass.
  const auto s = scene(cube(22, {true, true, true}), {{10, 1e3, {0.3, 11, 11}}}, 2500, unit, 1);
  const auto k = expect_same_as_all_pairs(s, 100);
  EXPECT_GE(k[0], 9);
}

TEST(StepperBigSpheres, OneBigSphereOfRatio20MatchesAllPairs) {
  // D = 20, M = 10^4 in a walled box (one cell then lists all pairs).
  const auto s = scene(cube(30, {false, false, false}), {{20, 1e4, {15, 15, 15}}}, 2000, unit, 2);
  const auto k = expect_same_as_all_pairs(s, 100);
  EXPECT_GE(k[0], 12);
}

TEST(StepperBigSpheres, FiveBigSpheresOfMixedSizesMatchAllPairs) {
  // Big against big by all pairs; two of them straddle periodic faces.
  const double nan = std::nan("");
  const auto s = scene(cube(22, {true, true, true}),
                       {{8, 500, {0.5, 5, 5}},
                        {6, 200, {11, 21.8, 11}},
                        {5, 125, {nan, nan, nan}},
                        {4, 64, {nan, nan, nan}},
                        {3, 27, {nan, nan, nan}}},
                       2000, unit, 3);
  expect_same_as_all_pairs(s, 100);
}

TEST(StepperBigSpheres, BigSpheresAcrossPeriodicFacesAndByWalls) {
  // Boundary p,p,w: one big sphere across the x and y faces, one 0.05 from the lower z wall,
  // one 0.05 from the upper.
  const auto s =
      scene(cube(22, {true, true, false}),
            {{7, 343, {21.5, 0.2, 11}}, {6, 216, {11, 11, 3.05}}, {5, 125, {5, 15, 22 - 2.55}}}, 2200, unit, 4);
  expect_same_as_all_pairs(s, 100);
}

TEST(StepperBigSpheres, UserGridFinerThanTheBigSphereIsAccepted) {
  // Cells 2.2 wide and a sphere 10 across: the pass covers it, so the grid is not refused.
  const auto s = scene(cube(22, {true, true, true}), {{10, 1e3, {11, 11, 11}}}, 2500, unit, 5);
  EXPECT_EQ(expect_same_as_all_pairs(s, 100, {10, 10, 10}), (std::array<int, 3>{10, 10, 10}));
}

TEST(StepperBigSpheres, LogNormalPolydisperseGasMatchesAllPairs) {
  // Diameters log-normal (median 1, s = 0.3): its largest spheres exceed two medians.
  const auto s = scene(cube(22, {true, true, true}), {}, 2500, lognormal, 6);
  ASSERT_GE(split_by_size(s).big.size(), 3u);
  expect_same_as_all_pairs(s, 100);
}

TEST(StepperBigSpheres, PeriodicBoxTooShortForTheBigSphereIsRefused) {
  // 19 across in a periodic box of 22: one cell is narrower than the sphere, and its pairs
  // through the minimum image would reach past half the box.
  const auto s = scene(cube(22, {true, true, true}), {{19, 1e3, {11, 11, 11}}}, 200, unit, 7);
  try {
    make_stepper(s, {}, StepperConfig{});
    FAIL() << "not refused";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("length 22"), std::string::npos) << what;
    EXPECT_NE(what.find("diameter 19"), std::string::npos) << what;
  }
}

TEST(StepperBigSpheres, EnergyAndMomentumConservedOverALongRun) {
  // Two big spheres (mass ratios 10^3 and 10^4) in a periodic gas, 3000 steps: every collision
  // conserves momentum and energy to round-off.
  const auto s = scene(cube(24, {true, true, true}), {{12, 1e4, {12, 12, 12}}, {6, 1e3, {3, 3, 3}}}, 2500, unit, 8);
  StepperConfig cfg;
  auto st = make_stepper(s, {}, cfg);
  st->run(3000);
  const auto out = st->state();
  EXPECT_GT(st->counters().collisions, 50000);
  const double e0 = kinetic_energy(s), e1 = kinetic_energy(out);
  EXPECT_LT(std::abs(e1 - e0) / e0, 1e-12);
  EXPECT_LT(norm(total_momentum(out) - total_momentum(s)), 1e-10);
  EXPECT_LT(max_overlap(out), 1e-9);
}

TEST(StepperBigSpheres, FloatRunsKeepEnergyWithUnitDiametersAndOneOddSphere) {
  // Unit diameters put a colliding pair's |dr|^2 a few ulps from 1, where a float square root in
  // the impulse leaned one way and gained energy at every collision (3e-6 over 10 time units
  // with one big sphere); the impulse needs none. Over 12 seeds the drift had mean -8e-9 and
  // sd 1.7e-8 (an unbiased random walk): 4e-7 is over 20 sd.
  const auto s = scene(cube(20, {true, true, true}), {{10, 1e3, {10, 10, 10}}}, 2500, unit, 11);
  StepperConfig cfg;
  auto st = make_stepper(s, {}, cfg, Precision::Float);
  st->run(1000);
  EXPECT_GT(st->counters().collisions, 30000);
  const double e0 = kinetic_energy(s);
  EXPECT_LT(std::abs(kinetic_energy(st->state()) - e0) / e0, 4e-7);
}

TEST(StepperBigSpheres, AutomaticGridDoesNotCollapseForOneLightFastBigSphere) {
  // One light big sphere at speed 5000 among unit spheres: the tuned skin (6 v_rms dt) is
  // several diameters, too thick for the big sphere's own pass in this box, and its grid was
  // one cell (all pairs at every rebuild, ~100x a good manual grid). The automatic choice must
  // keep a real grid (bench/auto_cells.py measures how close to the best manual one it runs).
  auto s = scene(cube(27.7, {true, true, true}), {{10, 5.2e-6, {13, 13, 13}}}, 3864, unit, 12);
  s.vel[0] = {3000, 3200, 2400};
  auto st = make_stepper(s, {}, StepperConfig{});
  EXPECT_GE(st->cells_per_dim()[0], 8);
  EXPECT_LT(st->skin(), 2.0);
  st->run(3);
  EXPECT_LT(max_overlap(st->state()), 1e-9);
}

TEST(StepperBigSpheres, ListGuardWatchesUnlistedBigSpheres) {
  // Cells 2 wide give a skin of 1. A small sphere and a big one (D = 6), unlisted at a gap of
  // 1.1, close it together: the one moving 0.8 per unit time becomes a mover past half the
  // skin, the other (0.45) never does. Only the mover's threats include its unlisted partner,
  // so the guard must find big spheres among them (and small ones for a big mover), or the
  // contact at t = 0.88 is missed. Compared with the all-pairs baseline.
  for (const double big_speed : {0.45, 0.8}) {
    ParticleSystem s;
    s.box = cube(24, {true, true, true});
    s.push_back(1, 1, 3.0, 1000, {12, 12, 12}, {big_speed, 0, 0});
    s.push_back(2, 1, 0.5, 1, {12 + 3.5 + 1.1, 12, 12}, {-(1.25 - big_speed), 0, 0});
    for (int k = 0; k < 20; ++k)  // at rest, far away: they make the median diameter 1
      s.push_back(3 + k, 1, 0.5, 1, {1.0 + k, 2, 2}, {0, 0, 0});
    StepperConfig grid, one;
    grid.cells = {12, 12, 12};
    one.cells = {1, 1, 1};
    auto a = make_stepper(s, {}, grid), b = make_stepper(s, {}, one);
    ASSERT_DOUBLE_EQ(a->skin(), 1.0);
    a->run(100);
    b->run(100);
    EXPECT_EQ(a->counters().collisions, 1) << "big sphere speed " << big_speed;
    EXPECT_EQ(b->counters().collisions, 1);
    const auto x = a->state(), y = b->state();
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_NEAR(x.pos[i].x, y.pos[i].x, 1e-12) << "sphere " << i + 1 << ", big sphere speed " << big_speed;
      EXPECT_NEAR(x.vel[i].x, y.vel[i].x, 1e-12) << "sphere " << i + 1 << ", big sphere speed " << big_speed;
    }
  }
}

TEST(BigSphereOverlaps, FoundWithoutAGridAsWideAsTheBigSphere) {
  // max_overlap and validate_and_wrap file only the small spheres in cells: overlaps of a big
  // sphere with a small one and with another big one must still be found, across a face.
  auto s = scene(cube(22, {true, true, true}), {{8, 500, {0.5, 11, 11}}, {6, 200, {11, 11, 11}}}, 1500, unit, 9);
  ASSERT_EQ(max_overlap(s), 0.0);
  s.pos[2] = {22 - 3.5 - 0.5 + 0.125, 11, 11};  // a small sphere 0.125 into the first big one, across x
  EXPECT_NEAR(max_overlap(s), 0.125, 1e-12);
  s.pos[1] = {0.5 + 7 - 0.25, 11, 11};  // the big ones 0.25 into each other (and into small ones)
  double brute = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      Vec3d dr = s.pos[i] - s.pos[j];
      for (int d = 0; d < 3; ++d) dr[d] -= 22 * std::nearbyint(dr[d] / 22);
      brute = std::max(brute, s.radius[i] + s.radius[j] - norm(dr));
    }
  EXPECT_NEAR(max_overlap(s), brute, 1e-12);
  ParticleSystem pair;  // only two big spheres overlap, by 0.25
  pair.box = cube(40, {true, true, true});
  pair.push_back(1, 1, 4, 500, {5, 20, 20}, {0, 0, 0});
  pair.push_back(2, 1, 4, 500, {5 + 8 - 0.25, 20, 20}, {0, 0, 0});
  pair.push_back(3, 1, 3, 200, {30, 30, 30}, {0, 0, 0});
  for (int k = 0; k < 10; ++k) pair.push_back(4 + k, 1, 0.5, 1, {20, 5 + 2.0 * k, 5}, {0, 0, 0});
  EXPECT_NEAR(max_overlap(pair), 0.25, 1e-12);
  // find_overlap names that pair (by index) and its distances; a slack above the overlap clears it.
  const auto o = find_overlap(pair);
  ASSERT_TRUE(o.has_value());
  EXPECT_EQ(std::min(o->i, o->j), 0u);
  EXPECT_EQ(std::max(o->i, o->j), 1u);
  EXPECT_NEAR(o->distance, 7.75, 1e-12);
  EXPECT_EQ(o->contact, 8.0);
  EXPECT_FALSE(find_overlap(pair, 0.3).has_value());
  try {
    validate_and_wrap(s, "scene");
    FAIL() << "overlap not refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("overlaps"), std::string::npos) << e.what();
  }
}

TEST(StepperBigSpheres, SinglePrecisionRunsThePassToo) {
  // The same pass in float: energy to float round-off, no overlap beyond it, and collision
  // totals within their statistical spread of the double run's: over 12 seeds the ratio had mean
  // 1.0003 and sd 0.78% (5% is 6 sd), the float drift sd 1e-8.
  const auto s = scene(cube(22, {true, true, true}), {{10, 1e3, {11, 11, 11}}}, 2500, unit, 10);
  StepperConfig cfg;
  auto d = make_stepper(s, {}, cfg, Precision::Double), f = make_stepper(s, {}, cfg, Precision::Float);
  d->run(500);
  f->run(500);
  EXPECT_EQ(f->cells_per_dim(), d->cells_per_dim());
  const auto out = f->state();
  EXPECT_LT(std::abs(kinetic_energy(out) / kinetic_energy(s) - 1), 1e-4);
  EXPECT_LT(max_overlap(out), 1e-4);
  EXPECT_NEAR(double(f->counters().collisions) / double(d->counters().collisions), 1.0, 0.05);
}
