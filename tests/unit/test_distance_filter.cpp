// The list scan's distance filter (one masked load per position with AVX-512VL, dot() otherwise)
// against |a - b|^2 in long double: its relative error must stay far inside the slack the scan
// widens its limit by, for coordinates across a box of 10^3 diameters and for near-contact pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "../../standalone/src/distance_filter.hpp"

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

}  // namespace

TEST(DistanceFilter, Float) { check_filter<float>(); }
TEST(DistanceFilter, Double) { check_filter<double>(); }
