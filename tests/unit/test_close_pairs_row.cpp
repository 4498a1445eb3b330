// The pair build's row kernel (vectorised with AVX-512 where the build targets it, scalar
// otherwise) against a plain loop: every row length 0..40 (whole vectors and every tail), equal
// and unequal radii, float and double, hits exactly the pairs inside the cut-off and nothing else.
// The block kernel (a cell's spheres against one run) against the row kernel, sphere by sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "stepper/close_pairs_row.hpp"

namespace {

template <class Real, bool Mono>
void check_rows() {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-2.0, 2.0), ur(0.2, 0.6);
  const std::size_t n = 48;
  std::vector<Real> x(n), y(n), z(n), r(n);
  const Real skin = Real(0.3), sigma = Real(1.0), cut2 = (sigma + skin) * (sigma + skin);
  for (int trial = 0; trial < 200; ++trial) {
    for (std::size_t k = 0; k < n; ++k)
      x[k] = Real(u(rng)), y[k] = Real(u(rng)), z[k] = Real(u(rng)), r[k] = Real(ur(rng));
    const hardsphere::detail::RowSoA<Real> soa{x.data(), y.data(), z.data(), r.data()};
    const std::uint32_t i = std::uint32_t(trial % 5);
    const Real px = Real(u(rng)), py = Real(u(rng)), pz = Real(u(rng)), ri = r[i];
    for (std::uint32_t j0 = 5; j0 < 8; ++j0)
      for (std::uint32_t j1 = j0; j1 <= j0 + 40; ++j1) {
        std::vector<std::uint32_t> out(2 * (40 + hardsphere::detail::kRowSlack) + 4, 0xdeadbeef);
        const std::size_t base = 2;  // pairs already in the list stay untouched
        out[0] = 11, out[1] = 12, out[2] = 13, out[3] = 14;
        const std::size_t got = hardsphere::detail::append_close_row<Real, Mono>(soa, i, px, py, pz, ri, skin, cut2, j0,
                                                                                 j1, out.data(), base);
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

//! append_close_block over spheres [i0, i1) and run [j0, j1) finds the same pairs as
//! append_close_row for each i (j > i only for `upper`, a run starting in i's cell), in any
//! order, writes nothing beyond its slack, and counts each pair once for both spheres.
template <class Real, bool Mono>
void check_blocks() {
  using hardsphere::detail::kRowSlack;
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> u(-1.5, 1.5), ur(0.2, 0.6);
  const std::size_t n = 64;
  std::vector<Real> x(n), y(n), z(n), r(n);
  const Real skin = Real(0.3), sigma = Real(1.0), cut2 = (sigma + skin) * (sigma + skin);
  std::size_t total = 0;
  for (int trial = 0; trial < 40; ++trial) {
    for (std::size_t k = 0; k < n; ++k)
      x[k] = Real(u(rng)), y[k] = Real(u(rng)), z[k] = Real(u(rng)), r[k] = Real(ur(rng));
    const hardsphere::detail::RowSoA<Real> soa{x.data(), y.data(), z.data(), r.data()};
    for (const bool upper : {false, true})
      for (std::uint32_t i0 = 0; i0 < 3; ++i0)
        for (std::uint32_t i1 = i0; i1 <= i0 + 5; ++i1)
          for (std::uint32_t j1 = i0 + 1; j1 <= i0 + 40; j1 += 3) {
            // upper: the run starts right after the first sphere of the cell, as in the stepper
            const std::uint32_t j0 = upper ? i0 + 1 : i1 + 2;
            if (j1 < j0) continue;
            const std::size_t base = 3, room = 2 * (base + (i1 - i0) * (j1 - j0) + kRowSlack);
            std::vector<std::uint32_t> got_out(room + 8, 0xdeadbeef), row_out(room + 8, 0xdeadbeef);
            std::vector<std::uint32_t> degree(n, 7u);  // counts add to what is there
            const std::size_t got = hardsphere::detail::append_close_block<Real, Mono>(
                soa, i0, i1, j0, j1, upper, skin, cut2, got_out.data(), base, degree.data());
            std::vector<std::uint32_t> want_degree(n, 7u);
            for (std::size_t k = base; k < got; ++k) ++want_degree[got_out[2 * k]], ++want_degree[got_out[2 * k + 1]];
            EXPECT_EQ(degree, want_degree) << "spheres [" << i0 << ", " << i1 << "), run [" << j0 << ", " << j1 << ")";
            std::size_t want = base;
            for (std::uint32_t i = i0; i < i1; ++i) {
              const std::uint32_t from = upper ? std::max(j0, i + 1) : j0;
              if (from < j1)
                want = hardsphere::detail::append_close_row<Real, Mono>(soa, i, x[i], y[i], z[i], r[i], skin, cut2,
                                                                        from, j1, row_out.data(), want);
            }
            ASSERT_EQ(got, want) << "spheres [" << i0 << ", " << i1 << "), run [" << j0 << ", " << j1 << ")";
            std::vector<std::pair<std::uint32_t, std::uint32_t>> a, b;
            for (std::size_t k = base; k < got; ++k) {
              a.emplace_back(got_out[2 * k], got_out[2 * k + 1]);
              b.emplace_back(row_out[2 * k], row_out[2 * k + 1]);
            }
            std::sort(a.begin(), a.end());
            std::sort(b.begin(), b.end());
            EXPECT_EQ(a, b);
            EXPECT_EQ(got_out[0], 0xdeadbeefu);  // the pairs before base are not touched
            for (std::size_t k = 2 * (got + kRowSlack); k < got_out.size(); ++k) ASSERT_EQ(got_out[k], 0xdeadbeefu);
            total += got - base;
          }
  }
  EXPECT_GT(total, 1000u);  // the scenes do produce pairs
}

}  // namespace

TEST(ClosePairsBlock, MonodisperseDouble) { check_blocks<double, true>(); }
TEST(ClosePairsBlock, MonodisperseFloat) { check_blocks<float, true>(); }
TEST(ClosePairsBlock, PolydisperseDouble) { check_blocks<double, false>(); }
TEST(ClosePairsBlock, PolydisperseFloat) { check_blocks<float, false>(); }

TEST(ClosePairsRow, MonodisperseDouble) { check_rows<double, true>(); }
TEST(ClosePairsRow, MonodisperseFloat) { check_rows<float, true>(); }
TEST(ClosePairsRow, PolydisperseDouble) { check_rows<double, false>(); }
TEST(ClosePairsRow, PolydisperseFloat) { check_rows<float, false>(); }
