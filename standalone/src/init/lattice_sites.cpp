#include "init/lattice_sites.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hardsphere {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Lowest allowed centre coordinate along axis d, and the length of the allowed range.
double lower(const Box& b, int d, double r) { return b.periodic[d] ? b.lo[d] : b.lo[d] + r; }
double span(const Box& b, int d, double r) { return b.periodic[d] ? b.length(d) : std::max(0.0, b.length(d) - 2 * r); }

using Counts = std::array<std::int64_t, 3>;

// FCC cells per axis: the fewest layers with >= n sites, each added along the widest cells.
Counts fcc_counts(const std::array<double, 3>& avail, std::int64_t n) {
  Counts k{1, 1, 1};
  while (4 * k[0] * k[1] * k[2] < n) {
    int widest = 0;
    for (int d = 1; d < 3; ++d)
      if (avail[d] / double(k[d]) > avail[widest] / double(k[widest])) widest = d;
    ++k[widest];
  }
  return k;
}

// Nearest FCC sites differ by half a cell along two axes, or by a whole cell along one.
double fcc_spacing(const std::array<double, 3>& avail, const Counts& k) {
  std::array<double, 3> h{};
  for (int d = 0; d < 3; ++d) h[d] = 0.5 * avail[d] / double(k[d]);
  double s = std::min({std::hypot(h[0], h[1]), std::hypot(h[0], h[2]), std::hypot(h[1], h[2])});
  for (int d = 0; d < 3; ++d)
    if (k[d] >= 2) s = std::min(s, 2 * h[d]);  // with one periodic cell that neighbour is the site itself
  return s;
}

// Plane spacing of a grid with m planes: periodic axes wrap, wall axes span the allowed range.
double grid_step(const Box& box, const std::array<double, 3>& avail, int d, std::int64_t m) {
  if (m < 2) return kInf;
  return box.periodic[d] ? avail[d] / double(m) : avail[d] / double(m - 1);
}

Counts grid_counts(const Box& box, const std::array<double, 3>& avail, std::int64_t n) {
  Counts m{1, 1, 1};
  while (m[0] * m[1] * m[2] < n) {
    int best = 0;
    for (int d = 1; d < 3; ++d)
      if (grid_step(box, avail, d, m[d] + 1) > grid_step(box, avail, best, m[best] + 1)) best = d;
    ++m[best];
  }
  return m;
}

double grid_spacing(const Box& box, const std::array<double, 3>& avail, const Counts& m) {
  double s = kInf;
  for (int d = 0; d < 3; ++d) s = std::min(s, grid_step(box, avail, d, m[d]));
  return s;
}

}  // namespace

LatticeSites lattice_sites(const Box& box, std::int64_t n, double radius) {
  std::array<double, 3> avail{}, low{};
  for (int d = 0; d < 3; ++d) {
    avail[d] = span(box, d, radius);
    low[d] = lower(box, d, radius);
  }
  n = std::max<std::int64_t>(n, 1);
  const Counts k = fcc_counts(avail, n), m = grid_counts(box, avail, n);
  const double s_fcc = fcc_spacing(avail, k), s_grid = grid_spacing(box, avail, m);
  LatticeSites out;
  if (s_fcc >= s_grid) {
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    out.spacing = s_fcc;
    out.pos.reserve(std::size_t(4 * k[0] * k[1] * k[2]));
    for (std::int64_t i = 0; i < k[0]; ++i)
      for (std::int64_t j = 0; j < k[1]; ++j)
        for (std::int64_t l = 0; l < k[2]; ++l)
          for (const auto& b : basis) {
            const std::int64_t idx[3] = {i, j, l};
            Vec3d p;
            // A quarter-cell offset keeps wall-axis sites inside the allowed range.
            for (int d = 0; d < 3; ++d) p[d] = low[d] + (double(idx[d]) + b[d] + 0.25) * avail[d] / double(k[d]);
            out.pos.push_back(p);
          }
    return out;
  }
  out.spacing = s_grid;
  out.pos.reserve(std::size_t(m[0] * m[1] * m[2]));
  auto coordinate = [&](int d, std::int64_t j) {
    if (box.periodic[d]) return low[d] + (double(j) + 0.5) * avail[d] / double(m[d]);
    if (m[d] == 1) return low[d] + 0.5 * avail[d];
    return std::min(low[d] + double(j) * avail[d] / double(m[d] - 1), low[d] + avail[d]);
  };
  for (std::int64_t i = 0; i < m[0]; ++i)
    for (std::int64_t j = 0; j < m[1]; ++j)
      for (std::int64_t l = 0; l < m[2]; ++l) out.pos.push_back({coordinate(0, i), coordinate(1, j), coordinate(2, l)});
  return out;
}

}  // namespace hardsphere
