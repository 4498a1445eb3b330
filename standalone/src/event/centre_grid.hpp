#pragma once
//! Where the event-driven engine finds a sphere's neighbour-list members: the spheres' list
//! centres, filed in a cell grid whose cells are at least (largest diameter + shell) / reach
//! wide, so the cells within reach of a sphere's own hold every centre in range. List centres
//! move only when a sphere rebuilds its list, so nothing ever crosses a cell.
//!
//! Big spheres (split_by_size) are not filed in cells, which are sized for the others: they
//! take the indices [nsmall, n) in every order, every query tests their centres in one pass,
//! and a big sphere's own query scans every cell its range overlaps.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "event/geometry.hpp"
#include "event/renumbering.hpp"

namespace hardsphere::event {

//! A sphere's list centre (its position when its neighbour list was built) and radius: what a
//! query reads about each sphere of the cells around, two per cache line.
struct Centre {
  double x, y, z, r;
};

class CentreGrid {
 public:
  CentreGrid() = default;
  //! The centres of spheres 0..n-1 filed; the last nbig are the big ones.
  CentreGrid(const EventGeometry& geo, const std::vector<Centre>& centres, std::size_t nbig);
  //! The spheres sorted by the cell of their position, big ones last in the order given: the
  //! internal order that the grid and the lists are first built in.
  static std::vector<std::uint32_t> filing_order(const EventGeometry& geo, const std::vector<Vec3d>& pos,
                                                 const std::vector<std::uint32_t>& big);

  bool is_big(int i) const { return i >= nsmall_; }
  int small_count() const { return nsmall_; }

  //! Sphere i's list centre is now c.
  void move(int i, const Centre& c) {
    if (is_big(i)) {
      set_big_centre(i, c);
    } else if (const auto k = geo_.cell_of(c.x, c.y, c.z); k != cc_[std::size_t(i)]) {
      unlink(i);
      cc_[std::size_t(i)] = k;
      link(i, c);
    } else {
      cell_ctr_[std::size_t(geo_.cell_index(k)) * std::size_t(cap_) + std::size_t(slot_of_[std::size_t(i)])] = c;
    }
  }

  //! Calls f(j, image) for every sphere j != i whose list centre is closer than sigma_ij + shell
  //! to p, sphere i's centre: the members of i's neighbour list. f must not change the grid.
  template <class F>
  void for_each_in_range(int i, Centre p, F&& f) const {
    if (is_big(i))
      for_each_small_near_big(p, f);
    else
      for_each_small_in_stencil(i, p, f);
    for_each_big_in_range(i, p, f);
  }

  //! The spheres cell by cell in Morton (Z-curve) order of the cells, big ones last: an order in
  //! which spheres close in space are close in memory.
  std::vector<int> locality_order() const;
  void permute(const Renumbering& r);

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();

  void link(int i, const Centre& c) {
    const std::size_t h = std::size_t(geo_.cell_index(cc_[std::size_t(i)]));
    if (fill_[h] == cap_) grow();
    slots_[h * std::size_t(cap_) + std::size_t(fill_[h])] = i;
    cell_ctr_[h * std::size_t(cap_) + std::size_t(fill_[h])] = c;
    slot_of_[std::size_t(i)] = fill_[h]++;
  }
  void unlink(int i) {
    const std::size_t h = std::size_t(geo_.cell_index(cc_[std::size_t(i)]));
    const int k = slot_of_[std::size_t(i)];
    const std::size_t from = h * std::size_t(cap_) + std::size_t(--fill_[h]);
    const int last = slots_[from];
    slots_[h * std::size_t(cap_) + std::size_t(k)] = last;
    cell_ctr_[h * std::size_t(cap_) + std::size_t(k)] = cell_ctr_[from];
    slot_of_[std::size_t(last)] = k;
  }
  void grow();
  void set_big_centre(int i, const Centre& c) {
    const std::size_t b = std::size_t(i - nsmall_);
    big_x_[b] = c.x, big_y_[b] = c.y, big_z_[b] = c.z;
    big_r_[b] = c.r;
  }

  //! Cells at offsets -reach..reach from cell c0 along axis d: cell coordinates and periodic
  //! image signs (cells beyond a wall are skipped). Returns the count.
  int axis_cells(int c0, int d, int* cells, int* sign) const {
    int k = 0;
    for (int o = -geo_.reach(); o <= geo_.reach(); ++o) {
      int c = c0 + o, s = 0;
      if (c < 0) {
        if (!geo_.periodic(std::size_t(d))) continue;
        c += geo_.cells(std::size_t(d));
        s = -1;
      } else if (c >= geo_.cells(std::size_t(d))) {
        if (!geo_.periodic(std::size_t(d))) continue;
        c -= geo_.cells(std::size_t(d));
        s = 1;
      }
      cells[k] = c;
      sign[k] = s;
      ++k;
    }
    return k;
  }

  //! The big spheres (other than i) whose centres are closer than sigma_ij + shell to p, at
  //! their nearest periodic image: the box is longer than twice every such range, so no other
  //! image can be in range.
  template <class F>
  void for_each_big_in_range(int i, Centre p, F& f) const {
    const std::size_t nb = big_x_.size();
    // Every rebuild runs this: a branch-free pass over all big spheres first, then the few in range.
    double half[3], l[3];
    for (std::size_t a = 0; a < 3; ++a) half[a] = geo_.periodic(a) ? 0.5 * geo_.len(a) : kInf, l[a] = geo_.len(a);
    double* __restrict gap = big_gap_.data();
    const double shell = geo_.shell();
    for (std::size_t b = 0; b < nb; ++b) {
      double dx = p.x - big_x_[b], dy = p.y - big_y_[b], dz = p.z - big_z_[b];
      dx = dx > half[0] ? dx - l[0] : (dx < -half[0] ? dx + l[0] : dx);
      dy = dy > half[1] ? dy - l[1] : (dy < -half[1] ? dy + l[1] : dy);
      dz = dz > half[2] ? dz - l[2] : (dz < -half[2] ? dz + l[2] : dz);
      const double range = p.r + big_r_[b] + shell;
      gap[b] = dx * dx + dy * dy + dz * dz - range * range;
    }
    for (std::size_t b = 0; b < nb; ++b) {
      const int j = nsmall_ + int(b);
      if (!(gap[b] < 0) || j == i) continue;
      const double d[3] = {p.x - big_x_[b], p.y - big_y_[b], p.z - big_z_[b]};
      int sgn[3];
      for (std::size_t a = 0; a < 3; ++a) sgn[a] = d[a] > half[a] ? 1 : (d[a] < -half[a] ? -1 : 0);
      f(j, std::uint32_t((sgn[0] + 1) + 3 * (sgn[1] + 1) + 9 * (sgn[2] + 1)));
    }
  }

  //! The spheres in cells whose centres are closer than sigma_ij + shell to p, a big sphere's:
  //! every cell within its largest such range, with the periodic image of each cell's offset.
  template <class F>
  void for_each_small_near_big(Centre p, F& f) const {
    const double pc[3] = {p.x, p.y, p.z};
    const double shell = geo_.shell();
    const double far = p.r + geo_.grid_r() + shell;
    const std::array<int, 3>& nc = geo_.cells();
    int from[3], to[3];
    for (std::size_t d = 0; d < 3; ++d) {
      // A margin of a millionth of a cell for the rounding of cell_of.
      from[d] = int(std::floor((pc[d] - far - geo_.lo(d)) / geo_.width(d) - 1e-6));
      to[d] = int(std::floor((pc[d] + far - geo_.lo(d)) / geo_.width(d) + 1e-6));
      if (!geo_.periodic(d)) from[d] = std::max(from[d], 0), to[d] = std::min(to[d], nc[d] - 1);
    }
    // An offset o is cell o mod nc of the image floor(o / nc); range < L / 2 keeps it in -1..1.
    auto wrap = [&](int o, std::size_t d, int& sg) {
      sg = o < 0 ? -1 : (o >= nc[d] ? 1 : 0);
      return o - sg * nc[d];
    };
    for (int oz = from[2]; oz <= to[2]; ++oz) {
      int sz;
      const int z = wrap(oz, 2, sz);
      for (int oy = from[1]; oy <= to[1]; ++oy) {
        int sy;
        const int y = wrap(oy, 1, sy);
        for (int ox = from[0]; ox <= to[0]; ++ox) {
          int sx;
          const int x = wrap(ox, 0, sx);
          const std::uint32_t img = std::uint32_t((sx + 1) + 3 * (sy + 1) + 9 * (sz + 1));
          const auto& sh = geo_.image_shift(img);
          const double px = p.x - sh[0], py = p.y - sh[1], pz = p.z - sh[2];
          const std::size_t h = std::size_t((z * nc[1] + y) * nc[0] + x);
          const std::size_t h0 = h * std::size_t(cap_);
          for (int u = 0; u < fill_[h]; ++u) {
            const Centre& o = cell_ctr_[h0 + std::size_t(u)];
            const double dx = px - o.x, dy = py - o.y, dz = pz - o.z;
            const double range = p.r + o.r + shell;
            if (dx * dx + dy * dy + dz * dz < range * range) f(slots_[h0 + std::size_t(u)], img);
          }
        }
      }
    }
  }

  //! The spheres in the cells around small sphere i's whose centres are in range of p.
  template <class F>
  void for_each_small_in_stencil(int i, Centre p, F& f) const {
    const auto& k = cc_[std::size_t(i)];
    const std::array<int, 3>& nc = geo_.cells();
    int cx[5], cy[5], cz[5], sx[5], sy[5], sz[5];
    const int kx = axis_cells(k[0], 0, cx, sx);
    const int ky = axis_cells(k[1], 1, cy, sy);
    const int kz = axis_cells(k[2], 2, cz, sz);
    // Pass 1: the stencil's cells and image codes; their lines are requested at once so the
    // cache misses overlap.
    int cell[125];
    std::uint32_t img[125];
    int ncell = 0;
    for (int a = 0; a < kz; ++a)
      for (int b = 0; b < ky; ++b) {
        const int row = (cz[a] * nc[1] + cy[b]) * nc[0];
        for (int e = 0; e < kx; ++e) {
          const std::size_t h = std::size_t(row + cx[e]);
          __builtin_prefetch(&fill_[h]);
          __builtin_prefetch(&slots_[h * std::size_t(cap_)]);
          __builtin_prefetch(&cell_ctr_[h * std::size_t(cap_)]);
          cell[ncell] = int(h);
          img[ncell++] = std::uint32_t((sx[e] + 1) + 3 * (sy[b] + 1) + 9 * (sz[a] + 1));
        }
      }
    // Pass 2: distance test of the centres, cell by cell.
    const Centre* ctr = cell_ctr_.data();
    for (int q = 0; q < ncell; ++q) {
      const std::size_t h0 = std::size_t(cell[q]) * std::size_t(cap_);
      const auto& sh = geo_.image_shift(img[q]);
      const double px = p.x - sh[0], py = p.y - sh[1], pz = p.z - sh[2];
      const int f_ = fill_[std::size_t(cell[q])];
      for (int u = 0; u < f_; ++u) {
        const Centre& o = ctr[h0 + std::size_t(u)];
        const double dx = px - o.x, dy = py - o.y, dz = pz - o.z;
        const double range = p.r + o.r + geo_.shell();
        if (dx * dx + dy * dy + dz * dz < range * range) {
          const int j = slots_[h0 + std::size_t(u)];
          if (j != i) f(j, img[q]);
        }
      }
    }
  }

  EventGeometry geo_;
  std::vector<std::array<int, 3>> cc_;  // cell coordinates of each sphere's list centre
  // Cell contents: fixed-capacity slot arrays, grown when a cell overflows. The centres are
  // stored in the cells too, so a query reads each cell sequentially instead of chasing one
  // cache line per sphere.
  std::vector<int> slots_;        // cell c holds slots_[c * cap_ .. c * cap_ + fill_[c])
  std::vector<Centre> cell_ctr_;  // the centres of those spheres, same layout
  std::vector<int> fill_, slot_of_;
  int cap_ = 8;
  std::vector<int> cell_order_;  // the cells in Morton order (locality_order())
  int nsmall_ = 0;
  std::vector<double> big_x_, big_y_, big_z_, big_r_;  // list centres of the big spheres (i - nsmall)
  mutable std::vector<double> big_gap_;                // scratch: squared distance - squared range
};

}  // namespace hardsphere::event
