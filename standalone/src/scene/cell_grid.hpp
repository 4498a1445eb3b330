#pragma once
//! Uniform cell grid ("space partitioning" boxes) over a Box. Knows cell counts, widths,
//! and which cells neighbour which, without duplicates when an axis has fewer than 3 cells.
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hardsphere/box.hpp"

namespace hardsphere {

class CellGrid {
 public:
  CellGrid() = default;
  //! Exactly `counts` cells per axis (each >= 1).
  CellGrid(const Box& box, std::array<int, 3> counts);
  //! As many cells per axis as fit with width >= min_width, but at most about max_cells in all.
  static CellGrid with_min_width(const Box& box, double min_width, std::int64_t max_cells);

  std::array<int, 3> counts() const { return counts_; }
  std::int64_t size() const { return std::int64_t(counts_[0]) * counts_[1] * counts_[2]; }
  double width(int d) const { return width_[d]; }

  //! Largest pair distance guaranteed to be found among neighbour cells (min image included):
  //! +inf when every axis is covered whole by the neighbour stencil.
  double reach() const;

  //! True when every periodic axis has at least 3 cells, so the 13 forward neighbours of a
  //! cell are distinct and a wrapped neighbour coordinate is the minimum image.
  bool half_stencil_ok() const {
    for (int d = 0; d < 3; ++d)
      if (periodic_[d] && counts_[d] < 3) return false;
    return true;
  }
  //! Cell of a point; points slightly outside the box are clamped to the edge cells.
  int cell_of(double x, double y, double z) const { return index(coord(x, 0), coord(y, 1), coord(z, 2)); }
  int coord(double x, int d) const {
    const double c = std::floor((x - lo_[d]) * inv_width_[d]);  // clamped before the int conversion
    return c >= 0 ? (c < double(counts_[d]) ? int(c) : counts_[d] - 1) : 0;
  }
  int index(int cx, int cy, int cz) const { return (cz * counts_[1] + cy) * counts_[0] + cx; }

  //! Calls f(neighbour cell) for each distinct cell adjacent to (or equal to) `cell`.
  template <class F>
  void for_each_neighbour(int cell, F&& f) const {
    const int cx = cell % counts_[0];
    const int cy = (cell / counts_[0]) % counts_[1];
    const int cz = cell / (counts_[0] * counts_[1]);
    int nx[3], ny[3], nz[3];
    const int kx = axis_neighbours(cx, 0, nx), ky = axis_neighbours(cy, 1, ny), kz = axis_neighbours(cz, 2, nz);
    for (int c = 0; c < kz; ++c)
      for (int b = 0; b < ky; ++b)
        for (int a = 0; a < kx; ++a) f(index(nx[a], ny[b], nz[c]));
  }

  //! Counting sort of points into cells: fills start (size()+1 offsets) and the permutation
  //! order[k] = index of the k-th point in cell order. cell[i] receives each point's cell.
  //! `point(i)` returns anything with .x, .y, .z.
  template <class Point>
  void sort(std::size_t n, Point&& point, std::vector<int>& cell, std::vector<std::uint32_t>& start,
            std::vector<std::uint32_t>& order) const {
    sort(
        n, point, [](std::size_t) { return false; }, cell, start, order);
  }
  //! The same, but the points with trailing(i) are filed in no cell: they follow the last cell
  //! in order (from start[size()] on, in index order) and get cell size().
  template <class Point, class Trailing>
  void sort(std::size_t n, Point&& point, Trailing&& trailing, std::vector<int>& cell,
            std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& order) const {
    const std::size_t nc = std::size_t(size());
    cell.resize(n);
    start.assign(nc + 2, 0);
    for (std::size_t i = 0; i < n; ++i) {
      if (trailing(i)) {
        cell[i] = int(nc);
      } else {
        const auto p = point(i);
        cell[i] = cell_of(double(p.x), double(p.y), double(p.z));
      }
      ++start[std::size_t(cell[i]) + 1];
    }
    for (std::size_t c = 0; c <= nc; ++c) start[c + 1] += start[c];
    order.resize(n);
    fill_.assign(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order[fill_[std::size_t(cell[i])]++] = std::uint32_t(i);
    start.pop_back();
  }

 private:
  int axis_neighbours(int c, int d, int* out) const;

  std::array<int, 3> counts_{1, 1, 1};
  std::array<double, 3> lo_{0, 0, 0}, width_{1, 1, 1}, inv_width_{1, 1, 1};
  std::array<bool, 3> periodic_{true, true, true};
  std::array<double, 3> length_{1, 1, 1};
  mutable std::vector<std::uint32_t> fill_;  // scratch for sort(), kept to avoid reallocation
};

}  // namespace hardsphere
