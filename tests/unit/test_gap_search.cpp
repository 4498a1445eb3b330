// The list guard's neighbour search against all pairs: every sphere whose gap to sphere i lies
// in the window is found, through periodic faces and next to walls, for equal and unequal radii,
// in double and float.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <vector>

#include "stepper/gap_search.hpp"

using namespace hardsphere;

namespace {

template <class Real, bool Mono>
void check_against_all_pairs(double tolerance) {
  const Box box = Box::from_lengths({9.0, 10.0, 11.0}, {true, true, false});
  const double skin = 0.5, r_max = 0.5, gap_lo = skin, gap_hi = 1.7 * skin;
  const CellGrid grid = CellGrid::with_min_width(box, 2 * r_max + skin, 1 << 20);
  ASSERT_GE(grid.counts()[0], 5);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 900;
  std::vector<Vec3d> pos(n);
  std::vector<double> rad(n);
  for (std::size_t k = 0; k < n; ++k) {
    for (int d = 0; d < 3; ++d) pos[k][d] = box.lo[d] + u(rng) * box.length(d);
    rad[k] = Mono ? r_max : 0.3 + 0.2 * u(rng);
  }
  std::vector<int> cell;
  std::vector<std::uint32_t> start, order;
  grid.sort(
      n, [&](std::size_t k) { return pos[k]; }, cell, start, order);
  std::vector<Real> x(n), y(n), z(n), r(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3d p = pos[order[k]];
    x[k] = Real(p.x), y[k] = Real(p.y), z[k] = Real(p.z), r[k] = Real(rad[order[k]]);
  }
  Vec3<Real> shift[27];
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c)
        shift[image_code(a, b, c)] = {Real(a * box.length(0)), Real(b * box.length(1)), Real(c * box.length(2))};
  const detail::CellSorted<Real> cells{&grid, &box, start.data(), {x.data(), y.data(), z.data(), r.data()}, shift};
  std::vector<std::uint32_t> scratch;
  std::size_t found_total = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    std::map<std::uint32_t, double> found;
    detail::for_each_gap_between<Real, Mono>(
        cells, i, Real(2 * r_max), Real(r_max), Real(gap_lo), Real(gap_hi), scratch,
        [&](std::uint32_t j, Real gap, std::uint8_t image) {
          EXPECT_EQ(found.count(j), 0u) << "sphere " << j << " found twice";
          // The image is the one the gap was measured through.
          const Vec3<Real> d = Vec3<Real>{x[i], y[i], z[i]} - shift[image] - Vec3<Real>{x[j], y[j], z[j]};
          EXPECT_NEAR(double(norm(d)) - double(r[i] + r[j]), double(gap), 1e-4 * (1 + double(gap_hi)));
          found[j] = double(gap);
        });
    found_total += found.size();
    for (std::uint32_t j = 0; j < n; ++j) {
      if (j == i) continue;
      double best = 1e300;  // the gap through the nearest image (x and y periodic)
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          const Vec3d d{double(x[i]) - double(x[j]) - a * box.length(0),
                        double(y[i]) - double(y[j]) - b * box.length(1), double(z[i]) - double(z[j])};
          best = std::min(best, norm(d) - (double(r[i]) + double(r[j])));
        }
      const bool inside = best >= gap_lo + tolerance && best < gap_hi - tolerance;
      const bool outside = best < gap_lo - tolerance || best >= gap_hi + tolerance;
      if (inside) {
        ASSERT_EQ(found.count(j), 1u) << "sphere " << j << " at gap " << best << " from " << i << " not found";
        EXPECT_NEAR(found[j], best, tolerance);
      }
      if (outside) {
        EXPECT_EQ(found.count(j), 0u) << "sphere " << j << " at gap " << best << " from " << i << " found";
      }
    }
  }
  EXPECT_GT(found_total, 5 * n);  // the window is not empty
}

}  // namespace

TEST(GapSearch, FindsEveryGapInTheWindowMonodisperseDouble) { check_against_all_pairs<double, true>(1e-9); }
TEST(GapSearch, FindsEveryGapInTheWindowPolydisperseDouble) { check_against_all_pairs<double, false>(1e-9); }
TEST(GapSearch, FindsEveryGapInTheWindowMonodisperseFloat) { check_against_all_pairs<float, true>(1e-4); }
