// The pair build's row kernel (vectorised with AVX-512 where the build targets it, scalar
// otherwise) against a plain loop: every row length 0..40 (whole vectors and every tail), equal
// and unequal radii, float and double, hits exactly the pairs inside the cut-off and nothing else.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "../../standalone/src/close_pairs_row.hpp"

namespace {

template <class Real, bool Mono>
void check_rows() {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-2.0, 2.0), ur(0.2, 0.6);
  const std::size_t n = 48;
  std::vector<Real> x(n), y(n), z(n), r(n);
  const Real skin = Real(0.3), sigma = Real(1.0), cut2 = (sigma + skin) * (sigma + skin);
  for (int trial = 0; trial < 200; ++trial) {
    for (std::size_t k = 0; k < n; ++k) x[k] = Real(u(rng)), y[k] = Real(u(rng)), z[k] = Real(u(rng)), r[k] = Real(ur(rng));
    const hardsphere::detail::RowSoA<Real> soa{x.data(), y.data(), z.data(), r.data()};
    const std::uint32_t i = std::uint32_t(trial % 5);
    const Real px = Real(u(rng)), py = Real(u(rng)), pz = Real(u(rng)), ri = r[i];
    for (std::uint32_t j0 = 5; j0 < 8; ++j0)
      for (std::uint32_t j1 = j0; j1 <= j0 + 40; ++j1) {
        std::vector<std::uint32_t> out(2 * (40 + hardsphere::detail::kRowSlack) + 4, 0xdeadbeef);
        const std::size_t base = 2;  // pairs already in the list stay untouched
        out[0] = 11, out[1] = 12, out[2] = 13, out[3] = 14;
        const std::size_t got = hardsphere::detail::append_close_row<Real, Mono>(soa, i, px, py, pz, ri, skin, cut2, j0, j1,
                                                                                 out.data(), base);
        std::vector<std::uint32_t> expect;
        for (std::uint32_t j = j0; j < j1; ++j) {
          const double dx = double(px) - double(x[j]), dy = double(py) - double(y[j]), dz = double(pz) - double(z[j]);
          const double c = Mono ? double(sigma + skin) : double(ri) + double(r[j]) + double(skin);
          if (dx * dx + dy * dy + dz * dz < c * c) expect.push_back(j);
        }
        ASSERT_EQ(got - base, expect.size()) << "row [" << j0 << ", " << j1 << ")";
        EXPECT_EQ(out[0], 11u);
        EXPECT_EQ(out[3], 14u);
        for (std::size_t k = 0; k < expect.size(); ++k) {
          EXPECT_EQ(out[2 * (base + k)], i);
          EXPECT_EQ(out[2 * (base + k) + 1], expect[k]);
        }
      }
  }
}

}  // namespace

TEST(ClosePairsRow, MonodisperseDouble) { check_rows<double, true>(); }
TEST(ClosePairsRow, MonodisperseFloat) { check_rows<float, true>(); }
TEST(ClosePairsRow, PolydisperseDouble) { check_rows<double, false>(); }
TEST(ClosePairsRow, PolydisperseFloat) { check_rows<float, false>(); }
