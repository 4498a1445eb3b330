// The stepper's drift kernel (AVX-512 blocks of 16 floats or 8 doubles plus a scalar tail, or
// the scalar loop alone) against a plain loop: every sphere count 0..50 (whole blocks and every
// tail), float and double, with and without speeds: positions, the recorded displacements
// (raised, never lowered), speeds and both maxima, to a few roundings, and the spheres it
// reports past the flag (in order, no other).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "stepper/drift_kernel.hpp"

namespace {

template <class Real>
void check_drift(bool with_speed) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> pos(-20.0, 20.0), vel(-3.0, 3.0), small(-0.4, 0.4), rec(0.0, 0.3);
  std::size_t total_flagged = 0;
  const Real dt = Real(0.013), tol = 8 * std::numeric_limits<Real>::epsilon();
  auto near = [&](double got, double want) { return std::fabs(got - want) <= tol * std::max(1.0, std::fabs(want)); };
  for (std::size_t n = 0; n <= 50; ++n) {
    std::vector<Real> p(3 * n), v(3 * n), p0(3 * n), d2(n), speed(n, Real(-1));
    for (std::size_t k = 0; k < 3 * n; ++k)
      p0[k] = Real(pos(rng)), p[k] = p0[k] + Real(small(rng)), v[k] = Real(vel(rng));
    for (std::size_t i = 0; i < n; ++i) d2[i] = Real(rec(rng)) * Real(rec(rng));
    const std::vector<Real> p_in = p, d2_in = d2;
    const Real floor = Real(0.01), flag = Real(0.2);
    std::vector<std::uint32_t> flagged(n + 1, 0xffffffffu);
    std::size_t n_flagged = 99;
    const auto mx = hardsphere::detail::drift_spheres<Real>(p.data(), v.data(), p0.data(), d2.data(),
                                                            with_speed ? speed.data() : nullptr, n, dt, floor, flag,
                                                            flagged.data(), n_flagged);
    std::vector<std::uint32_t> want_flagged;
    for (std::uint32_t i = 0; i < n; ++i)
      if (d2[i] >= flag) want_flagged.push_back(i);
    ASSERT_EQ(n_flagged, want_flagged.size()) << "n " << n;
    for (std::size_t k = 0; k < n_flagged; ++k) EXPECT_EQ(flagged[k], want_flagged[k]);
    total_flagged += n_flagged;
    double want_m = floor, want_v2 = 0;
    for (std::size_t i = 0; i < n; ++i) {
      double dd = 0, vv = 0;
      for (int c = 0; c < 3; ++c) {
        const double moved = double(p_in[3 * i + c]) + double(v[3 * i + c]) * double(dt);
        ASSERT_TRUE(near(p[3 * i + c], moved)) << "n " << n << " sphere " << i;
        const double d = double(p[3 * i + c]) - double(p0[3 * i + c]);
        dd += d * d, vv += double(v[3 * i + c]) * double(v[3 * i + c]);
      }
      EXPECT_TRUE(near(d2[i], std::max(dd, double(d2_in[i])))) << "n " << n << " sphere " << i;
      EXPECT_GE(d2[i], d2_in[i]);
      if (with_speed)
        EXPECT_TRUE(near(speed[i], std::sqrt(vv))) << "n " << n << " sphere " << i;
      else
        EXPECT_EQ(speed[i], Real(-1));
      want_m = std::max(want_m, dd), want_v2 = std::max(want_v2, vv);
    }
    EXPECT_TRUE(near(mx.d2, want_m)) << "n " << n;
    EXPECT_TRUE(near(mx.v2, want_v2)) << "n " << n;
  }
  EXPECT_GT(total_flagged, 100u);  // the scenes do flag spheres, some but not all (1275 in all)
  EXPECT_LT(total_flagged, 1175u);
}

}  // namespace

TEST(DriftKernel, Float) { check_drift<float>(true); }
TEST(DriftKernel, FloatNoSpeeds) { check_drift<float>(false); }
TEST(DriftKernel, Double) { check_drift<double>(true); }
TEST(DriftKernel, DoubleNoSpeeds) { check_drift<double>(false); }
