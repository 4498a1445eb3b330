// The list scan's distance filter (one masked load per position with AVX-512VL, dot() otherwise)
// against |a - b|^2 in long double: its relative error must stay far inside the slack the scan
// widens its limit by, for coordinates across a box of 10^3 diameters and for near-contact pairs.
// The run filter (four pairs at a time with AVX-512VL) against that test pair by pair, for every
// run length 0..40 (whole groups and every tail).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "stepper/distance_filter.hpp"

namespace {

template <class Real>
void check_filter() {
  using hardsphere::Vec3;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> where(0.0, 1000.0), dir(-1.0, 1.0), gap(0.9, 1.5);
  const double slack = double(hardsphere::detail::kDistanceFilterSlack<Real>) - 1.0;
  const double eps = double(std::numeric_limits<Real>::epsilon());
  double worst = 0;
  for (int k = 0; k < 100000; ++k) {
    // a pair at distance ~1 anywhere in the box: the differences are exact-ish, the sum is not
    const Vec3<Real> a{Real(where(rng)), Real(where(rng)), Real(where(rng))};
    Vec3<double> u{dir(rng), dir(rng), dir(rng)};
    const double len = std::sqrt(u.x * u.x + u.y * u.y + u.z * u.z), r = gap(rng);
    const Vec3<Real> b{Real(a.x + r * u.x / len), Real(a.y + r * u.y / len), Real(a.z + r * u.z / len)};
    const Vec3<Real> d = a - b;  // the scan's exact test takes these same differences
    const long double ex = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z;
    const double got = double(hardsphere::detail::distance2_filter(a, b));
    worst = std::max(worst, double(std::fabs((long double)got - ex) / ex));
  }
  EXPECT_LT(worst, 4 * eps);  // a few roundings of the sum of three squares
  if (slack > 0) {
    EXPECT_GT(slack, 100 * worst);  // the widening covers them many times over
  }
}

template <class Real>
void check_runs() {
  using hardsphere::Vec3;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  const std::size_t n = 60;
  std::vector<Vec3<Real>> pos(n);
  std::size_t total = 0;
  for (int trial = 0; trial < 50; ++trial) {
    for (auto& p : pos) p = {Real(u(rng)), Real(u(rng)), Real(u(rng))};
    for (std::uint32_t len = 0; len <= 40; ++len) {
      std::vector<std::uint32_t> pairs(2 * len), hits(len + 4, 0xffffffffu);
      for (auto& x : pairs) x = std::uint32_t(rng() % n);
      const Real lim2 = Real(1.2);
      const std::uint32_t got = hardsphere::detail::filter_pairs(pos.data(), pairs.data(), len, lim2, hits.data());
      std::vector<std::uint32_t> want;
      for (std::uint32_t k = 0; k < len; ++k)
        if (hardsphere::detail::distance2_filter(pos[pairs[2 * k]], pos[pairs[2 * k + 1]]) < lim2) want.push_back(k);
      // The vector path sums the squares in its own order: a pair within rounding of the limit
      // may differ; none of these random pairs is that close (checked below), so all must agree.
      for (std::uint32_t k = 0; k < len; ++k) {
        const Vec3<Real> d = pos[pairs[2 * k]] - pos[pairs[2 * k + 1]];
        ASSERT_GT(std::fabs(double(hardsphere::dot(d, d)) - double(lim2)), 1e-5) << "a pair at the limit";
      }
      ASSERT_EQ(got, want.size()) << "run of " << len;
      for (std::uint32_t h = 0; h < got; ++h) EXPECT_EQ(hits[h], want[h]);
      total += got;
    }
  }
  EXPECT_GT(total, 1000u);
}

}  // namespace

TEST(DistanceFilter, RunsFloat) { check_runs<float>(); }
TEST(DistanceFilter, RunsDouble) { check_runs<double>(); }
TEST(DistanceFilter, Float) { check_filter<float>(); }
TEST(DistanceFilter, Double) { check_filter<double>(); }
