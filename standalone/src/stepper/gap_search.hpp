#pragma once
//! Which spheres have a given gap to sphere i? For the stepper's list guard: the spheres j whose
//! gap |x_i - x_j| - (r_i + r_j) lies in [gap_lo, gap_hi), found from the cell-sorted coordinates
//! of the last rebuild with the pair build's row kernel, one row of cells along x at a time.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/neighbour_entry.hpp"
#include "hardsphere/box.hpp"
#include "hardsphere/vec3.hpp"
#include "scene/cell_grid.hpp"
#include "stepper/close_pairs_row.hpp"

namespace hardsphere::detail {

//! Spheres sorted by cell: sphere k of cell c is at soa[cell_start[c] + ...]; image_shift by
//! image code (see image_code()).
template <class Real>
struct CellSorted {
  const CellGrid* grid;
  const Box* box;
  const std::uint32_t* cell_start;
  RowSoA<Real> soa;  //!< radii needed unless Mono
  const Vec3<Real>* image_shift;
};

//! Calls push(j, gap, image) for every sphere j filed in a cell (i itself excluded only by
//! gap_lo > -2 r_i) with gap_lo <= gap < gap_hi, gap = |x_i - x_j - shift| - sigma_ij over the
//! periodic images within one box length, shift = image_shift[image]. Mono: sigma_ij = sigma for all pairs; otherwise
//! r_i + r_j, and max_radius bounds r_j. Needs the reach r_i + max_radius + gap_hi below half of every periodic axis,
//! so that one image at most is within it; `rows` is scratch.
template <class Real, bool Mono, class Push>
void for_each_gap_between(const CellSorted<Real>& s, std::uint32_t i, Real sigma, Real max_radius, Real gap_lo,
                          Real gap_hi, std::vector<std::uint32_t>& rows, Push&& push) {
  const Vec3<Real> p{s.soa.x[i], s.soa.y[i], s.soa.z[i]};
  const Real ri = Mono ? sigma / Real(2) : s.soa.r[i];
  const Real reach = (Mono ? sigma : ri + max_radius) + gap_hi;
  const CellGrid& grid = *s.grid;
  const Box& box = *s.box;
  const auto k = grid.counts();
  int lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    const double w = grid.width(d), x = double(p[d]) - box.lo[d];
    lo[d] = int(std::floor((x - double(reach)) / w));
    hi[d] = int(std::floor((x + double(reach)) / w));
    if (!box.periodic[d]) lo[d] = std::max(lo[d], 0), hi[d] = std::min(hi[d], k[d] - 1);
  }
  auto wrap = [&](int x, int d, int& image) {
    image = x < 0 ? -1 : (x >= k[d] ? 1 : 0);
    return x - image * k[d];
  };
  // Distance from i to the slab of cells c along axis d (0 inside): rows of cells beyond reach
  // in y and z are skipped (the corners of the block).
  auto slab_gap = [&](int c, int d) {
    const double w = grid.width(d), x = double(p[d]) - box.lo[d];
    return std::max({double(c) * w - x, x - double(c + 1) * w, 0.0});
  };
  const double reach2 = double(reach) * double(reach);
  const Real cut = (Mono ? sigma : Real(0)) + gap_hi;  // the row kernel's cut-off for Mono
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y) {
      const double gy = slab_gap(y, 1), gz = slab_gap(z, 2);
      if (gy * gy + gz * gz >= reach2) continue;
      int iy, iz;
      const int cy = wrap(y, 1, iy), cz = wrap(z, 2, iz);
      for (int x0 = lo[0]; x0 <= hi[0];) {
        int ix, ix1;
        const int cx0 = wrap(x0, 0, ix);
        int x1 = x0;  // the run [x0, x1] has one image
        while (x1 < hi[0] && (wrap(x1 + 1, 0, ix1), ix1 == ix)) ++x1;
        const std::uint32_t j0 = s.cell_start[grid.index(cx0, cy, cz)];
        const std::uint32_t j1 = s.cell_start[grid.index(cx0 + (x1 - x0), cy, cz) + 1];
        x0 = x1 + 1;
        if (j0 == j1) continue;
        const std::uint8_t image = image_code(ix, iy, iz);
        const Vec3<Real> pi = p - s.image_shift[image];
        rows.resize(2 * (j1 - j0 + kRowSlack));
        const std::size_t n =
            append_close_row<Real, Mono>(s.soa, i, pi.x, pi.y, pi.z, ri, gap_hi, cut * cut, j0, j1, rows.data(), 0);
        for (std::size_t h = 0; h < n; ++h) {
          const std::uint32_t j = rows[2 * h + 1];
          const Real dx = pi.x - s.soa.x[j], dy = pi.y - s.soa.y[j], dz = pi.z - s.soa.z[j];
          const Real gap = std::sqrt(dx * dx + dy * dy + dz * dz) - (Mono ? sigma : ri + s.soa.r[j]);
          if (gap >= gap_lo && gap < gap_hi) push(j, gap, image);
        }
      }
    }
}

}  // namespace hardsphere::detail
