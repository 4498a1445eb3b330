// Big spheres in the event engine (spheres over kBigOverMedian median diameters, kept out of the
// cell grid): collision by collision against the all-pairs reference, conservation over many
// events, and periodic boxes shorter than three big diameters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "event_reference.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/rng.hpp"
#include "scene/size_classes.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

struct Sphere {
  double diameter, mass;
};

//! Spheres placed by random sequential addition, given ones first at their places and the rest
//! largest first at random places clear of those before (and of the walls); Maxwell-Boltzmann
//! velocities at T = 1 (a big sphere moves slowly).
ParticleSystem scene(std::array<double, 3> length, std::array<bool, 3> periodic, std::vector<Sphere> spheres,
                     std::uint64_t seed, const std::vector<Vec3d>& fixed = {}) {
  Rng rng(seed);
  ParticleSystem s;
  s.box = Box::from_lengths(length, periodic);
  std::stable_sort(spheres.begin() + std::ptrdiff_t(fixed.size()), spheres.end(),
                   [](const Sphere& a, const Sphere& b) { return a.diameter > b.diameter; });
  auto clear = [&](Vec3d p, double r) {
    for (int d = 0; d < 3; ++d)
      if (!periodic[std::size_t(d)] && (p[d] < r || p[d] > length[std::size_t(d)] - r)) return false;
    for (std::size_t j = 0; j < s.size(); ++j) {
      Vec3d dr = p - s.pos[j];
      for (int d = 0; d < 3; ++d)
        if (periodic[std::size_t(d)]) dr[d] -= length[std::size_t(d)] * std::nearbyint(dr[d] / length[std::size_t(d)]);
      if (norm(dr) < r + s.radius[j] + 1e-3) return false;
    }
    return true;
  };
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const double r = spheres[k].diameter / 2, m = spheres[k].mass;
    Vec3d p = k < fixed.size() ? fixed[k] : Vec3d{0, 0, 0};
    for (int attempt = 0; k >= fixed.size() && attempt < 100000; ++attempt) {
      p = {rng.uniform() * length[0], rng.uniform() * length[1], rng.uniform() * length[2]};
      if (clear(p, r)) break;
    }
    EXPECT_TRUE(clear(p, r)) << "no room for sphere " << k;
    const double v = 1 / std::sqrt(m);
    s.push_back(std::int64_t(k + 1), k < fixed.size() ? 2 : 1, r, m, p,
                {v * rng.normal(), v * rng.normal(), v * rng.normal()});
  }
  return s;
}

//! The unit spheres of `gas` with big spheres put at `at`, the unit spheres they would overlap removed.
ParticleSystem with_big(const ParticleSystem& gas, const std::vector<Sphere>& big, const std::vector<Vec3d>& at) {
  ParticleSystem s;
  s.box = gas.box;
  for (std::size_t b = 0; b < big.size(); ++b)
    s.push_back(std::int64_t(b + 1), 2, big[b].diameter / 2, big[b].mass, at[b],
                (1 / std::sqrt(big[b].mass)) * gas.vel[b]);
  for (std::size_t i = 0; i < gas.size(); ++i) {
    bool clear = true;
    for (std::size_t b = 0; b < big.size(); ++b) {
      Vec3d dr = gas.pos[i] - at[b];
      for (int d = 0; d < 3; ++d) dr[d] -= gas.box.length(d) * std::nearbyint(dr[d] / gas.box.length(d));
      clear = clear && norm(dr) > big[b].diameter / 2 + gas.radius[i];
    }
    if (clear) s.push_back(std::int64_t(big.size() + i + 1), 1, gas.radius[i], gas.mass[i], gas.pos[i], gas.vel[i]);
  }
  return s;
}

std::vector<Sphere> units(std::size_t n) { return std::vector<Sphere>(n, Sphere{1.0, 1.0}); }

std::vector<Sphere> with(std::vector<Sphere> big, const std::vector<Sphere>& small) {
  big.insert(big.end(), small.begin(), small.end());
  return big;
}

double box_for(const std::vector<Sphere>& spheres, double phi) {
  double v = 0;
  for (const auto& s : spheres) v += M_PI / 6 * s.diameter * s.diameter * s.diameter;
  return std::cbrt(v / phi);
}

}  // namespace

TEST(EventBigSpheres, OneBigSphereRatio10AgreesWithAllPairsReference) {
  // Diameter 10, mass 1000, among 1500 unit spheres at phi 0.2: a box of 18.7, shorter than
  // three big diameters (refused before big spheres were kept out of the cells); both stencils.
  const auto sp = with({{10, 1000}}, units(1500));
  const double l = box_for(sp, 0.2);
  const auto s = scene({l, l, l}, {true, true, true}, sp, 1, {{l / 2, l / 2, l / 2}});
  ASSERT_EQ(split_by_size(s).big.size(), 1u);
  ASSERT_LT(l, 30.0);
  test::expect_same_as_reference(s, EventConfig{}, 1.2, 12, 2000);
  EventConfig wide;  // the 5x5x5 stencil for the small spheres
  wide.reach = 2;
  test::expect_same_as_reference(s, wide, 1.2, 12, 2000);
}

TEST(EventBigSpheres, OneBigSphereRatio20AgreesWithAllPairsReference) {
  // Diameter 20, mass 1e4, among 2500 unit spheres at phi 0.3 (the small ones at ~0.1 around it).
  const auto sp = with({{20, 1e4}}, units(2500));
  const double l = box_for(sp, 0.3);
  const auto s = scene({l, l, l}, {true, true, true}, sp, 2, {{l / 2, l / 2, l / 2}});
  ASSERT_EQ(split_by_size(s).big.size(), 1u);
  test::expect_same_as_reference(s, EventConfig{}, 1.0, 10, 1500);
}

TEST(EventBigSpheres, FiveMixedBigSpheresAgreeWithAllPairsReference) {
  // Diameters 3 to 7 with masses d^3 and one light one (mass 1 at diameter 4), among 1200 unit
  // spheres: big-big pairs, and big spheres fast enough to leave their shells. With the thin
  // shell the clock is re-based and the spheres renumbered every 1200 events.
  const auto sp = with({{7, 343}, {6, 216}, {5, 125}, {4, 1}, {3, 27}}, units(1200));
  const double l = box_for(sp, 0.25);
  const auto s = scene({l, l, l}, {true, true, true}, sp, 3,
                       {{0.2 * l, 0.2 * l, 0.2 * l},
                        {0.7 * l, 0.3 * l, 0.5 * l},
                        {0.3 * l, 0.75 * l, 0.7 * l},
                        {0.75 * l, 0.75 * l, 0.2 * l},
                        {0.5 * l, 0.5 * l, 0.9 * l}});
  ASSERT_EQ(split_by_size(s).big.size(), 5u);
  for (double shell : {0.05, 0.6}) {
    EventConfig cfg;
    Physics cfg_physics;
    cfg.shell = shell;
    if (shell < 0.1) cfg.rebase_events_per_sphere = 1;
    test::expect_same_as_reference(s, cfg, 0.8, 10, 1500);
  }
}

TEST(EventBigSpheres, AcrossPeriodicFacesAndNextToWallsAgreeWithAllPairsReference) {
  // Periodic in x and y, walls in z. One big sphere (diameter 8, mass 64) straddles the x and y
  // faces and nearly touches the lower wall, a second (diameter 6) nearly touches the upper one;
  // both move fast enough to cross faces and bounce off the walls during the run.
  const auto sp = with({{8, 64}, {6, 27}}, units(1000));
  const std::array<double, 3> len{16, 16, 14};
  auto s = scene(len, {true, true, false}, sp, 4, {{0.2, 15.9, 4.05}, {8, 8, 10.95}});
  s.vel[0] = {-0.6, 0.5, -0.3};
  s.vel[1] = {0.5, -0.4, 0.4};
  ASSERT_EQ(split_by_size(s).big.size(), 2u);
  test::expect_same_as_reference(s, EventConfig{}, 1.0, 10, 1500);
}

TEST(EventBigSpheres, LogNormalPolydisperseGasAgreesWithAllPairsReference) {
  // 1200 spheres with log-normal diameters (median 1, s = 0.35) and masses d^3: a few percent
  // are over two median diameters, so many big spheres, of many sizes, meet each other.
  Rng rng(5);
  std::vector<Sphere> sp;
  for (int k = 0; k < 1200; ++k) {
    const double d = std::exp(0.35 * rng.normal());
    sp.push_back({d, d * d * d});
  }
  const double l = box_for(sp, 0.25);
  auto s = scene({l, l, l}, {true, true, true}, sp, 6);
  ASSERT_GE(split_by_size(s).big.size(), 10u);
  test::expect_same_as_reference(s, EventConfig{}, 0.5, 10, 1000);
}

TEST(EventBigSpheres, ConserveEnergyAndMomentumOverManyEvents) {
  // Three big spheres (diameters 12, 8, 5; mass ratio up to 1e4) put into 8000 unit spheres at
  // phi 0.25 (those they would overlap removed), ~1e6 events: energy and momentum to round-off,
  // no overlap beyond 1e-10 diameters, checked every ~3e5 events (max_overlap's cells are as wide
  // as the largest sphere, so each check is slow).
  const double l = std::cbrt(8000 * M_PI / 6 / 0.25);
  const auto s = with_big(test::gas(8000, 0.25, 7), {{12, 1e4}, {8, 512}, {5, 125}},
                          {{0.25 * l, 0.25 * l, 0.25 * l}, {0.75 * l, 0.7 * l, 0.6 * l}, {0.2 * l, 0.8 * l, 0.7 * l}});
  const double e0 = kinetic_energy(s);
  const Vec3d p0 = total_momentum(s);
  EventEngine e(s);
  double worst = 0;
  for (int k = 0; k < 4; ++k) {
    e.advance(5.0);
    worst = std::max(worst, max_overlap(e.state()));
  }
  EXPECT_GT(e.counters().events, 1000000);
  const auto out = e.state();
  EXPECT_LT(std::abs(kinetic_energy(out) - e0) / e0, 1e-12);
  double pscale = 0;
  for (std::size_t i = 0; i < s.size(); ++i) pscale += s.mass[i] * norm(s.vel[i]);
  EXPECT_LT(norm(total_momentum(out) - p0), 1e-12 * pscale);
  EXPECT_LT(worst, 1e-10);
}

TEST(EventBigSpheres, UnderGravityKeepTheirEnergy) {
  // Gravity along z (walls), one big sphere (diameter 6, mass 216) in 2000 unit spheres: the
  // big sphere falls and bounces on parabolas with the others; kinetic + potential energy is
  // kept to 1e-9 and nothing overlaps.
  const auto sp = with({{6, 216}}, units(2000));
  const std::array<double, 3> len{16, 16, 20};
  const auto s = scene(len, {true, true, false}, sp, 9, {{8, 8, 14}});
  EventConfig cfg;
  Physics cfg_physics;
  cfg_physics.gravity = {0, 0, -0.5};
  const double e0 = kinetic_energy(s) + potential_energy(s, cfg_physics.gravity);
  EventEngine e(s, cfg_physics, cfg);
  e.advance(20.0);
  const auto out = e.state();
  EXPECT_GT(e.counters().collisions, 50000);
  EXPECT_LT(out.pos[0].z, 10.0);  // the big sphere has sunk
  EXPECT_LT(std::abs(kinetic_energy(out) + potential_energy(out, cfg_physics.gravity) - e0) / e0, 1e-9);
  EXPECT_LT(max_overlap(out), 1e-10);
}

TEST(EventBigSpheres, BoxSizeRules) {
  // One big sphere (diameter 10) among unit spheres: a periodic axis needs three cells of the
  // small spheres and more than twice the largest contact distance (2 x 5.5 = 11) plus a shell.
  auto make = [](double lx) {
    Rng rng(8);
    ParticleSystem s;
    s.box = Box::from_lengths({lx, 20, 20}, {true, true, true});
    s.push_back(1, 2, 5.0, 1000, {lx / 2, 10, 10}, {0.01, 0, 0});
    int id = 2;
    for (double y : {1.0, 3.0, 17.0, 19.0})
      for (double z : {1.0, 3.0, 17.0, 19.0})
        s.push_back(id++, 1, 0.5, 1, {0.5, y, z}, {rng.normal(), rng.normal(), rng.normal()});
    return s;
  };
  EXPECT_THROW(EventEngine e(make(11.0)), InputError);
  EXPECT_NO_THROW(EventEngine e(make(11.5)));
  // At 12.5 the shell is what the big pair's range leaves of half the box: 6.25 - 5.5.
  const auto s = make(12.5);
  EventEngine e(s);
  EXPECT_NEAR(e.shell(), 0.75, 1e-6);
  const ParticleSystem small = [&] {
    ParticleSystem u = s;
    u.radius[0] = 0.5;  // no big sphere: the old rule, three unit diameters, is enough
    return u;
  }();
  EXPECT_NO_THROW(EventEngine e2(small));
  const double e0 = kinetic_energy(s);
  e.advance(30.0);
  EXPECT_GT(e.counters().collisions, 20);
  EXPECT_LT(std::abs(kinetic_energy(e.state()) - e0) / e0, 1e-12);
  EXPECT_LT(max_overlap(e.state()), 1e-10);
}
