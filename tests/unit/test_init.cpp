// Initial-state generation: the lattice route's sites for every N and box shape (the site
// count loop used to cycle forever for most N), the end-to-end case that hung, and the
// refusals of impossible or unreachable requests.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "hardsphere/errors.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/particles.hpp"
#include "init/lattice_sites.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

// A box of n spheres of radius 0.5 at packing fraction phi, edge ratios `shape`.
Box box_for(std::int64_t n, double phi, std::array<double, 3> shape, std::array<bool, 3> periodic) {
  const double v = double(n) * M_PI / 6.0 / phi;
  const double s = std::cbrt(v / (shape[0] * shape[1] * shape[2]));
  return Box::from_lengths({s * shape[0], s * shape[1], s * shape[2]}, periodic);
}

// Smallest distance between two sites (minimum image), by brute force over a cell-free scan of
// a sample of sites against all.
double min_distance(const Box& box, const std::vector<Vec3d>& pos, std::size_t sample) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t step = std::max<std::size_t>(1, pos.size() / sample);
  for (std::size_t i = 0; i < pos.size(); i += step)
    for (std::size_t j = 0; j < pos.size(); ++j) {
      if (i == j) continue;
      Vec3d dr = pos[i] - pos[j];
      for (int d = 0; d < 3; ++d)
        if (box.periodic[d]) dr[d] -= box.length(d) * std::nearbyint(dr[d] / box.length(d));
      best = std::min(best, norm(dr));
    }
  return best;
}

void expect_inside(const Box& box, const std::vector<Vec3d>& pos, double r, const std::string& what) {
  for (const auto& p : pos)
    for (int d = 0; d < 3; ++d) {
      const double lo = box.periodic[d] ? box.lo[d] : box.lo[d] + r, hi = box.periodic[d] ? box.hi[d] : box.hi[d] - r;
      ASSERT_GE(p[d], lo) << what;
      ASSERT_LE(p[d], hi) << what;
    }
}

}  // namespace

TEST(LatticeSites, EveryNFrom1To20000InACubeEndsWithEnoughWellSpacedSites) {
  // The old count loop recomputed the layers from scratch on every pass and cycled forever
  // whenever one extra layer was not enough (N = 9..13, 49..62, 145, ..., 4500 at any phi).
  for (std::int64_t n = 1; n <= 20000; ++n) {
    const Box box = box_for(n, 0.3, {1, 1, 1}, {true, true, true});
    const auto s = lattice_sites(box, n, 0.5);
    ASSERT_GE(std::int64_t(s.pos.size()), n) << "n " << n;
    // FCC spacing of a perfect fit is 1.12 (V/N)^(1/3); a layer too many costs at most 35%.
    ASSERT_GE(s.spacing, 0.7 * std::cbrt(box.volume() / double(n))) << "n " << n;
  }
}

TEST(LatticeSites, WallsAndShapesKeepTheRouteAtItsStartingRadius) {
  // The route starts at radius min(r (0.3/phi)^(1/3), 0.49 spacing): well-spaced sites leave
  // that at >= 85% of its dilute value for every N >= 50, whatever the walls and shape.
  const std::array<bool, 3> boundaries[] = {{false, false, false}, {true, true, false}, {true, false, false}};
  const std::array<double, 3> shapes[] = {{1, 1, 1}, {1, 1, 3}, {2, 2, 1}};
  for (const auto& periodic : boundaries)
    for (const auto& shape : shapes)
      for (const double phi : {0.3, 0.55})
        for (std::int64_t n = 1; n <= 6000; n += (n < 300 ? 1 : 37)) {
          const Box box = box_for(n, phi, shape, periodic);
          const auto s = lattice_sites(box, n, 0.5);
          ASSERT_GE(std::int64_t(s.pos.size()), n);
          ASSERT_GT(s.spacing, 0.0);
          if (n >= 50) {
            ASSERT_GE(0.49 * s.spacing, 0.85 * 0.5 * std::cbrt(0.3 / phi)) << "n " << n << " phi " << phi;
          }
        }
}

TEST(LatticeSites, ClaimedSpacingIsTheTrueSpacingAndSitesStayInside) {
  struct Case {
    std::int64_t n;
    std::array<double, 3> len;
    std::array<bool, 3> periodic;
  };
  const Case cases[] = {
      {1, {1, 1, 1}, {false, false, false}},  // one sphere filling a walled box
      {2, {2, 2, 2}, {true, true, true}},     // two diameters: the smallest periodic box
      {3, {1.5, 2.5, 3.5}, {false, true, false}},
      {10, {1, 1, 100}, {false, false, true}},  // a line: walls one diameter apart on x, y
      {10, {1, 1, 100}, {false, false, false}},
      {400, {1, 40, 40}, {false, true, true}},  // a monolayer
      {400, {1.0000001, 30, 30}, {false, true, true}},
      {4500, {20.8, 20.8, 20.8}, {true, true, true}},  // the case that hung (phi 0.3)
      {1000, {50, 5, 5}, {true, false, false}},
      {2000, {15, 15, 15}, {false, false, false}},
  };
  for (const auto& c : cases) {
    const Box box = Box::from_lengths(c.len, c.periodic);
    const auto s = lattice_sites(box, c.n, 0.5);
    const std::string what = "n " + std::to_string(c.n) + " box " + std::to_string(c.len[0]);
    ASSERT_GE(std::int64_t(s.pos.size()), c.n) << what;
    expect_inside(box, s.pos, 0.5, what);
    if (s.pos.size() == 1) continue;
    const double true_spacing = min_distance(box, s.pos, 200);
    EXPECT_GT(true_spacing, 0.0) << what;
    EXPECT_NEAR(true_spacing, s.spacing, 1e-9 * (1 + s.spacing)) << what;
  }
}

TEST(LatticeSites, LargeNAndLongThinBoxesTakeLinearTime) {
  // A few million sites, and a line of 10^5 (every layer along one axis): both finish at once.
  const auto big = lattice_sites(box_for(3000000, 0.5, {1, 1, 1}, {true, true, true}), 3000000, 0.5);
  EXPECT_GE(big.pos.size(), 3000000u);
  EXPECT_GT(big.spacing, 0.7 * std::cbrt(M_PI / 6 / 0.5));
  const Box line = Box::from_lengths({1, 1, 2e5}, {false, false, true});
  const auto s = lattice_sites(line, 100000, 0.5);
  EXPECT_GE(s.pos.size(), 100000u);
  EXPECT_NEAR(s.spacing, 2.0, 1e-9);
}

TEST(InitLatticeRoute, TheHangingCaseFinishes) {
  // hardsphere run --n 4500 --phi 0.3 never returned; nor did --init lattice for most N.
  const auto s = test::gas(4500, 0.3, 1);
  EXPECT_EQ(s.size(), 4500u);
  EXPECT_EQ(max_overlap(s), 0.0);
  EXPECT_NEAR(s.packing_fraction(), 0.3, 1e-12);
  for (const std::int64_t n : {9, 10, 13, 49, 62, 145}) {
    const auto t = test::gas(n, 0.5, 2);
    EXPECT_EQ(t.size(), std::size_t(n));
    EXPECT_EQ(max_overlap(t), 0.0) << "n " << n;
  }
}

TEST(InitLatticeRoute, NarrowBoxesAndFewSpheres) {
  // A line of spheres between walls barely more than one diameter apart (FCC sites there share
  // lines), a monolayer, and n = 1, 2, 3: every one is made in bounded time. Walls exactly one
  // diameter apart are refused: a sphere between them would bounce infinitely often.
  InitSpec spec;
  spec.method = InitMethod::Lattice;
  spec.n = 20;
  spec.box = Box::from_lengths({1, 1, 30}, {false, false, true});
  EXPECT_THROW(make_initial_state(spec), InputError);
  spec.box = Box::from_lengths({1.05, 1.05, 30}, {false, false, true});
  auto s = make_initial_state(spec);
  EXPECT_EQ(s.size(), 20u);
  EXPECT_EQ(max_overlap(s), 0.0);
  spec.n = 200;
  spec.box = Box::from_lengths({1.2, 18, 18}, {false, true, true});
  s = make_initial_state(spec);
  EXPECT_EQ(s.size(), 200u);
  for (const std::int64_t n : {1, 2, 3}) {
    spec.n = n;
    spec.box = Box::from_lengths({2.2, 2.2, 2.2}, {true, true, false});
    s = make_initial_state(spec);
    EXPECT_EQ(s.size(), std::size_t(n));
    EXPECT_EQ(max_overlap(s), 0.0);
  }
}

TEST(InitLatticeRoute, JammedSmallWalledBoxesAreRefusedNotRunForever) {
  // Walls lower the packing fraction at which the route's compression jams; near it the
  // collisions per step grow without bound (N = 20 between walls at 0.50 had not finished after
  // a minute). A collision budget per sphere stops it; auto then tries the dense generator,
  // which cannot reach these either and says how far it got.
  InitSpec spec;
  spec.n = 20;
  spec.method = InitMethod::Lattice;
  spec.box = box_for(20, 0.50, {1, 1, 1}, {false, false, false});
  try {
    make_initial_state(spec);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("jammed near 0.4"), std::string::npos) << e.what();
  }
  spec.n = 50;
  spec.method = InitMethod::Auto;
  spec.box = box_for(50, 0.55, {1, 1, 1}, {false, false, false});
  try {
    make_initial_state(spec);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("densest packing reached was 0.5"), std::string::npos) << e.what();
  }
}

TEST(InitInput, MoreSpheresThanTheEnginesHoldAreRefusedUpFront) {
  // Refused before any site list or pair list is allocated.
  InitSpec spec;
  spec.n = std::int64_t(1) << 40;
  spec.box = box_for(spec.n, 0.3, {1, 1, 1}, {true, true, true});
  try {
    make_initial_state(spec);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1099511627776"), std::string::npos) << e.what();
  }
}

TEST(InitInput, RefusalsNameThePackingFractionAndTheLimit) {
  auto message = [](InitSpec spec) {
    try {
      make_initial_state(spec);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  InitSpec spec;
  spec.n = 1000;
  spec.box = box_for(1000, 0.80, {1, 1, 1}, {true, true, true});
  std::string m = message(spec);
  EXPECT_NE(m.find("0.8"), std::string::npos) << m;
  EXPECT_NE(m.find("close packing 0.74"), std::string::npos) << m;
  spec.box = box_for(1000, 0.70, {1, 1, 1}, {true, true, true});
  m = message(spec);
  EXPECT_NE(m.find("0.7 "), std::string::npos) << m;
  EXPECT_NE(m.find(std::to_string(kDenseLimit).substr(0, 4)), std::string::npos) << m;
  spec.method = InitMethod::Lattice;
  spec.box = box_for(1000, 0.60, {1, 1, 1}, {true, true, true});
  m = message(spec);
  EXPECT_NE(m.find("0.6 "), std::string::npos) << m;
  EXPECT_NE(m.find("0.55"), std::string::npos) << m;
  EXPECT_NE(m.find("--init dense"), std::string::npos) << m;
  spec.method = InitMethod::Random;
  spec.box = box_for(1000, 0.45, {1, 1, 1}, {true, true, true});
  m = message(spec);
  EXPECT_NE(m.find("--init lattice"), std::string::npos) << m;
  EXPECT_EQ(parse_init_method("dense"), InitMethod::Dense);
  EXPECT_THROW(parse_init_method("crystal"), InputError);
}
