#include "stepper/pair_list.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace hardsphere::detail {

template <class Real, bool Mono>
void PairList<Real, Mono>::build(const Vec3<Real>* pos, const Real* radius, const std::uint32_t* cell_start,
                                 std::size_t n, std::uint32_t big_begin) {
  pos_ = pos, radius_ = radius, cell_start_ = cell_start;
  n_ = std::uint32_t(n), big_begin_ = big_begin;
  near_.clear();
  wrap_.clear();
  wrap_image_.clear();
  adj_start_.assign(n + 1, 0);  // each sphere's list length, counted where its pairs are found
  if (g_.grid->half_stencil_ok())
    build_half_stencil();
  else
    build_any_grid();
  if (big_begin_ < n_) build_big_pairs();
  build_adjacency();
}

template <class Real, bool Mono>
HS_ALWAYS_INLINE int PairList<Real, Mono>::stencil_runs(std::int64_t c, const std::array<int, 3>& at,
                                                        CellRun* const first) const {
  // Every periodic axis has >= 3 cells: the 13 forward neighbours of a cell are distinct, and
  // wrapping a neighbour's cell coordinate gives exactly the pair's minimum image, so each
  // unordered pair of neighbouring cells is met once and no pair needs a division.
  // Forward rows (dy, dz) whose x range is [dx_lo, 1]: the cell's own row only ahead of it.
  static const int rows[5][3] = {{1, 0, 0}, {-1, 1, 0}, {-1, -1, 1}, {-1, 0, 1}, {-1, 1, 1}};
  const CellGrid& grid = *g_.grid;
  const Box& box = *g_.box;
  const auto k = grid.counts();
  const int cx = at[0], cy = at[1], cz = at[2];  // cell c's coordinates
  if (cx >= 1 && cx + 1 < k[0] && k[0] >= 4 && cy >= 1 && cy + 1 < k[1] && cz + 1 < k[2]) {
    // Inside the grid the five runs are offsets (with 4 or more cells along x none of them
    // touch, so none merge).
    const int row = k[0], layer = k[0] * k[1], ci = int(c);
    for (int r = 0; r < 5; ++r) {
      const int begin = ci + rows[r][0] + rows[r][1] * row + rows[r][2] * layer;
      first[r] = {begin, ci + 2 + rows[r][1] * row + rows[r][2] * layer, kNoImage};
    }
    return 5;
  }
  CellRun* out = first;
  for (const auto& row : rows) {
    int ny = cy + row[1], nz = cz + row[2], iy = 0, iz = 0;
    if (ny < 0 || ny >= k[1]) {
      if (!box.periodic[1]) continue;
      iy = ny < 0 ? -1 : 1;  // across the lower face j's nearest image is one box down
      ny = (ny + k[1]) % k[1];
    }
    if (nz < 0 || nz >= k[2]) {
      if (!box.periodic[2]) continue;
      iz = nz < 0 ? -1 : 1;
      nz = (nz + k[2]) % k[2];
    }
    // Split the x range [cx + dx_lo, cx + 1] where it leaves the box.
    for (int x = cx + row[0]; x <= cx + 1; ++x) {
      int nx = x, ix = 0;
      if (nx < 0 || nx >= k[0]) {
        if (!box.periodic[0]) continue;
        ix = nx < 0 ? -1 : 1;
        nx = (nx + k[0]) % k[0];
      }
      const int cell = grid.index(nx, ny, nz);
      const std::uint8_t image = image_code(ix, iy, iz);
      if (out != first && out[-1].end == cell && out[-1].image == image)
        ++out[-1].end;  // extends the previous run
      else
        *out++ = {cell, cell + 1, image};
    }
  }
  return int(out - first);
}

template <class Real, bool Mono>
void PairList<Real, Mono>::build_half_stencil() {
  const Real mono_cut = list_cut(g_.sigma), mono_cut2 = mono_cut * mono_cut;
  const CellGrid& grid = *g_.grid;
  const std::int64_t ncell = grid.size();
  // A cell's spheres against each run of consecutive spheres go to append_close_block
  // (vectorised where the CPU allows); pairs across a periodic face (rare) take push_pair.
  static_assert(sizeof(Pair) == 2 * sizeof(std::uint32_t) && offsetof(Pair, j) == sizeof(std::uint32_t));
  std::size_t n_near = 0;
  near_.resize(std::max<std::size_t>(near_.size(), 1024));
  std::uint32_t* degree = adj_start_.data() + 1;  // list lengths, see build()
  const RowSoA<Real> soa{soa_x_.data(), soa_y_.data(), soa_z_.data(), radius_};
  const auto counts = grid.counts();
  std::array<int, 3> at{-1, 0, 0};  // cell c's coordinates, x fastest
  for (std::int64_t c = 0; c < ncell; ++c) {
    if (++at[0] == counts[0]) {
      at[0] = 0;
      if (++at[1] == counts[1]) at[1] = 0, ++at[2];
    }
    const std::uint32_t b0 = cell_start_[c], b1 = cell_start_[c + 1];
    if (b0 == b1) continue;
    CellRun runs[kMaxRuns];
    const int nruns = stencil_runs(c, at, runs);
    std::size_t reach = b1 - b0;  // an upper bound of the pairs this cell can add
    for (int r = 0; r < nruns; ++r) reach += cell_start_[runs[r].end] - cell_start_[runs[r].begin];
    const std::size_t need = n_near + (b1 - b0) * reach + kRowSlack;
    if (need > near_.size()) near_.resize(2 * need);
    // The cell's own row (after i) and a first run that starts at the next cell without an
    // image (the +x neighbour, unless x wraps) are contiguous: one row.
    int first = 0;
    std::uint32_t own_end = b1;
    if (nruns > 0 && runs[0].begin == c + 1 && runs[0].image == kNoImage) {
      own_end = cell_start_[runs[0].end];
      first = 1;
    }
    auto* out = reinterpret_cast<std::uint32_t*>(near_.data());
    n_near =
        append_close_block<Real, Mono>(soa, b0, b1, b0 + 1, own_end, true, g_.skin, mono_cut2, out, n_near, degree);
    for (int r = first; r < nruns; ++r) {
      const std::uint32_t e0 = cell_start_[runs[r].begin], e1 = cell_start_[runs[r].end];
      if (runs[r].image == kNoImage) {
        n_near = append_close_block<Real, Mono>(soa, b0, b1, e0, e1, false, g_.skin, mono_cut2, out, n_near, degree);
        continue;
      }
      // Across a periodic face (rare): the row test with i's image, into a scratch buffer.
      for (std::uint32_t i = b0; i < b1; ++i) {
        const Vec3<Real> pis = pos_[i] - g_.image_shift[runs[r].image];
        wrap_row_.resize(2 * (e1 - e0 + kRowSlack));
        const std::size_t hits = append_close_row<Real, Mono>(soa, i, pis.x, pis.y, pis.z, Mono ? Real(0) : radius_[i],
                                                              g_.skin, mono_cut2, e0, e1, wrap_row_.data(), 0);
        for (std::size_t k = 0; k < hits; ++k) push_pair(i, wrap_row_[2 * k + 1], runs[r].image);
      }
    }
  }
  near_.resize(n_near);
}

template <class Real, bool Mono>
void PairList<Real, Mono>::build_any_grid() {
  // General grids (an axis with 1 or 2 periodic cells): neighbour cells may repeat, so take
  // each unordered cell pair once by index and the minimum image per pair.
  const CellGrid& grid = *g_.grid;
  const std::int64_t ncell = grid.size();
  for (std::int64_t c = 0; c < ncell; ++c) {
    const std::uint32_t b0 = cell_start_[c], b1 = cell_start_[c + 1];
    if (b0 == b1) continue;
    grid.for_each_neighbour(int(c), [&](int nb) {
      if (nb < c) return;
      const std::uint32_t e1 = cell_start_[nb + 1];
      for (std::uint32_t i = b0; i < b1; ++i) {
        for (std::uint32_t j = (nb == c ? i + 1 : cell_start_[nb]); j < e1; ++j) push_if_near(i, j);
      }
    });
  }
}

template <class Real, bool Mono>
void PairList<Real, Mono>::push_if_near(std::uint32_t i, std::uint32_t j) {
  Vec3<Real> d = pos_[i] - pos_[j];
  int k[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a)
    if (g_.box->periodic[a]) {
      k[a] = int(std::nearbyint(d[a] / g_.length[a]));
      d[a] -= Real(k[a]) * g_.length[a];
    }
  const Real cut = list_cut(radius_[i] + radius_[j]);
  if (dot(d, d) < cut * cut) push_pair(i, j, image_code(k[0], k[1], k[2]));
}

template <class Real, bool Mono>
void PairList<Real, Mono>::build_big_pairs() {
  // Each big sphere against the small ones in every cell its reach overlaps, then big against
  // big by all pairs; minimum images, stored lower index first like every pair.
  for (std::uint32_t b = big_begin_; b < n_; ++b) {
    for_each_gap_between<Real, false>(
        cells(), b, g_.sigma, g_.cell_radius, -std::numeric_limits<Real>::infinity(), g_.skin, threat_scratch_,
        [&](std::uint32_t j, Real, std::uint8_t image) { push_pair(j, b, std::uint8_t(26 - image)); });
    for (std::uint32_t c = b + 1; c < n_; ++c) push_if_near(b, c);
  }
}

template <class Real, bool Mono>
void PairList<Real, Mono>::build_adjacency() {
  // Both directions, CSR, for sweeping one sphere's neighbours; (j, i) carries the mirrored image.
  const std::size_t n = n_, np = near_.size() + wrap_.size();
  // adj_start_[i + 1] holds sphere i's list length, counted by the pair build.
  for (std::size_t i = 0; i < n; ++i) adj_start_[i + 1] += adj_start_[i];
  adj_.resize(2 * np);
  adj_cursor_.assign(adj_start_.begin(), adj_start_.end() - 1);
  auto add = [&](std::uint32_t i, std::uint32_t j, std::uint8_t image) {
    adj_[adj_cursor_[i]++] = adj_entry(j, image);
    adj_[adj_cursor_[j]++] = adj_entry(i, std::uint8_t(26 - image));
  };
  for (const auto& p : near_) add(p.i, p.j, kNoImage);
  adj_plain_end_.assign(adj_cursor_.begin(), adj_cursor_.end());  // each row: pairs without an image first
  for (std::size_t k = 0; k < wrap_.size(); ++k) add(wrap_[k].i, wrap_[k].j, wrap_image_[k]);
}

template class PairList<float, true>;
template class PairList<float, false>;
template class PairList<double, true>;
template class PairList<double, false>;

}  // namespace hardsphere::detail
