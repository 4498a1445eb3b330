#include "scene/cell_grid.hpp"

#include <algorithm>
#include <limits>

namespace hardsphere {

CellGrid::CellGrid(const Box& box, std::array<int, 3> counts) : counts_(counts) {
  for (int d = 0; d < 3; ++d) {
    lo_[d] = box.lo[d];
    length_[d] = box.length(d);
    periodic_[d] = box.periodic[d];
    width_[d] = length_[d] / counts_[d];
    inv_width_[d] = counts_[d] / length_[d];
  }
}

CellGrid CellGrid::with_min_width(const Box& box, double min_width, std::int64_t max_cells) {
  std::array<int, 3> k{};
  // Counts are capped in floating point first: a huge box over a tiny width must not overflow int.
  const double cap = double(std::max<std::int64_t>(max_cells, 1));
  for (int d = 0; d < 3; ++d) k[d] = int(std::clamp(std::floor(box.length(d) / min_width), 1.0, std::min(cap, 1e6)));
  // Too many nearly empty cells cost more to sort and scan than they save: widen them.
  while (std::int64_t(k[0]) * k[1] * k[2] > std::max<std::int64_t>(max_cells, 1)) {
    int widest = 0;
    for (int d = 1; d < 3; ++d)
      if (k[d] > k[widest]) widest = d;
    k[widest] = std::max(1, k[widest] * 9 / 10);
  }
  return CellGrid(box, k);
}

double CellGrid::reach() const {
  double r = std::numeric_limits<double>::infinity();
  for (int d = 0; d < 3; ++d) {
    if (counts_[d] >= 3) r = std::min(r, width_[d]);
    // One or two periodic cells cover the axis, but the stored minimum image is only
    // unambiguous for separations below half the box.
    else if (periodic_[d])
      r = std::min(r, 0.5 * length_[d]);
  }
  return r;
}

int CellGrid::axis_neighbours(int c, int d, int* out) const {
  const int k = counts_[d];
  if (k == 1) {
    out[0] = 0;
    return 1;
  }
  if (k == 2) {  // both cells are neighbours of each other, on either side
    out[0] = 0;
    out[1] = 1;
    return 2;
  }
  int m = 0;
  for (int o = -1; o <= 1; ++o) {
    int n = c + o;
    if (n < 0 || n >= k) {
      if (!periodic_[d]) continue;
      n = (n + k) % k;
    }
    out[m++] = n;
  }
  return m;
}

}  // namespace hardsphere
