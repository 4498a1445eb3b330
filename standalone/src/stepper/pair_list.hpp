#pragma once
//! The stepper's candidate pairs: every pair closer than r_i + r_j + skin when the list was
//! built, from the cell-sorted spheres. Pairs inside the box (most) are in near(), pairs across a
//! periodic face in wrap() with their image codes; adjacency() holds both directions per sphere
//! for the resolver's neighbour sweeps. Cells are searched by the half stencil (13 forward
//! neighbours as runs of consecutive cells) where every periodic axis has 3 cells or more, by all
//! neighbour cells otherwise; big spheres (filed in no cell, after the last one) by a pass of
//! their own. The list also answers the list guard's question: which spheres have a given gap.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/always_inline.hpp"
#include "common/default_init_allocator.hpp"
#include "common/neighbour_entry.hpp"
#include "hardsphere/box.hpp"
#include "hardsphere/vec3.hpp"
#include "scene/cell_grid.hpp"
#include "stepper/close_pairs_row.hpp"
#include "stepper/gap_search.hpp"

namespace hardsphere::detail {

template <class Real, bool Mono>
class PairList {
 public:
  struct Pair {
    std::uint32_t i, j;
  };
  //! What stays fixed from one build to the next.
  struct Geometry {
    const CellGrid* grid = nullptr;
    const Box* box = nullptr;  //!< from 0 to L (the stepper's frame)
    std::array<Real, 3> length{};
    const Vec3<Real>* image_shift = nullptr;  //!< 27 shifts by image code
    Real skin = 0;
    Real sigma = 0;        //!< Mono: the diameter
    Real cell_radius = 0;  //!< largest radius of the spheres filed in cells
    Real max_radius = 0;   //!< largest radius of all
  };
  void configure(const Geometry& g) { g_ = g; }

  //! The coordinate arrays of the next build (n spheres), which the stepper fills as it sorts.
  Real* x(std::size_t n) { return resized(soa_x_, n); }
  Real* y(std::size_t n) { return resized(soa_y_, n); }
  Real* z(std::size_t n) { return resized(soa_z_, n); }

  //! Builds the list over n cell-sorted spheres (positions also in x/y/z()), radius indexed like
  //! them; the spheres from big_begin on are big (big_begin == n: none).
  void build(const Vec3<Real>* pos, const Real* radius, const std::uint32_t* cell_start, std::size_t n,
             std::uint32_t big_begin);

  const std::vector<Pair, DefaultInitAllocator<Pair>>& near() const { return near_; }
  const std::vector<Pair>& wrap() const { return wrap_; }
  const std::vector<std::uint8_t>& wrap_image() const { return wrap_image_; }
  //! Both directions, CSR: row s holds adj_entry(partner, image of r_s - r_partner); its entries
  //! before plain_end[s] have no image.
  const std::uint32_t* adj_start() const { return adj_start_.data(); }
  const std::uint32_t* adj() const { return adj_.data(); }
  const std::uint32_t* adj_plain_end() const { return adj_plain_end_.data(); }

  //! Calls push(j, gap_ij) for every sphere j with skin <= gap < 2 kMaxMove skin at the last
  //! build (the list guard's threats of sphere i), gaps rounded down by a margin.
  template <class Push>
  void for_each_threat(std::uint32_t i, Real max_move, Push& push) const;

 private:
  struct CellRun {
    int begin, end;
    std::uint8_t image;
  };
  static constexpr int kMaxRuns = 10;
  static Real* resized(std::vector<Real>& v, std::size_t n) {
    v.resize(n);
    return v.data();
  }
  CellSorted<Real> cells() const {
    return {g_.grid, g_.box, cell_start_, {soa_x_.data(), soa_y_.data(), soa_z_.data(), radius_}, g_.image_shift};
  }
  //! Called per cell of every build: inlined into it, as its small loops are.
  HS_ALWAYS_INLINE int stencil_runs(std::int64_t c, const std::array<int, 3>& at, CellRun* out) const;
  void build_half_stencil();
  void build_any_grid();
  void build_big_pairs();
  void build_adjacency();
  //! Calls push(b, gap) for each big sphere b != i with gap_lo <= gap_ib < gap_hi (minimum image).
  template <class Push>
  void for_each_big_gap(std::uint32_t i, Real gap_lo, Real gap_hi, Push&& push) const;
  //! Adds a pair found outside the block kernel (which counts its own) and counts it.
  void push_pair(std::uint32_t i, std::uint32_t j, std::uint8_t image) {
    ++adj_start_[i + 1], ++adj_start_[j + 1];
    if (image == kNoImage)
      near_.push_back({i, j});
    else {
      wrap_.push_back({i, j});
      wrap_image_.push_back(image);
    }
  }
  //! Lists i and j if their nearest images are within the list's reach (builds that do not go by
  //! the half stencil: any grid, big spheres among themselves).
  void push_if_near(std::uint32_t i, std::uint32_t j);
  //! Candidate cut-off of a pair: contact distance plus skin (an infinite skin takes all).
  Real list_cut(Real contact) const {
    return std::isinf(g_.skin) ? std::numeric_limits<Real>::max() / 4 : contact + g_.skin;
  }

  Geometry g_;
  // The current build's inputs (valid until the next build).
  const Vec3<Real>* pos_ = nullptr;
  const Real* radius_ = nullptr;
  const std::uint32_t* cell_start_ = nullptr;
  std::uint32_t n_ = 0, big_begin_ = 0;
  std::vector<Pair, DefaultInitAllocator<Pair>> near_;  // grown and cut back at every build
  std::vector<Pair> wrap_;
  std::vector<std::uint8_t> wrap_image_;
  std::vector<Real> soa_x_, soa_y_, soa_z_;
  std::vector<std::uint32_t> wrap_row_;                // one row's pairs across a periodic face
  mutable std::vector<std::uint32_t> threat_scratch_;  // one row's spheres within reach
  std::vector<std::uint32_t> adj_start_, adj_, adj_cursor_, adj_plain_end_;
};

template <class Real, bool Mono>
template <class Push>
void PairList<Real, Mono>::for_each_threat(std::uint32_t i, Real max_move, Push& push) const {
  // The guard's window, gap < 2 max_move skin, keeps sigma + gap below sigma + 2 skin: two cell
  // widths, or half a periodic axis for big spheres. Gaps are computed again here, so a margin
  // covers their rounding against the build's: pairs at the list's edge count as threats, and
  // gaps are rounded down.
  const Real eps = Real(1e-4) * (Real(2) * g_.max_radius + g_.skin);
  const Real window = Real(2) * max_move * g_.skin;
  for_each_gap_between<Real, Mono>(cells(), i, g_.sigma, g_.cell_radius, g_.skin - eps, window + eps, threat_scratch_,
                                   [&](std::uint32_t j, Real gap, std::uint8_t) { push(j, gap - eps); });
  for_each_big_gap(i, g_.skin - eps, window + eps, [&](std::uint32_t b, Real gap) { push(b, gap - eps); });
}

template <class Real, bool Mono>
template <class Push>
void PairList<Real, Mono>::for_each_big_gap(std::uint32_t i, Real gap_lo, Real gap_hi, Push&& push) const {
  // The box is longer than twice any big sphere's reach, so the minimum image is the only one
  // that can be this close.
  const Box& box = *g_.box;
  for (std::uint32_t b = big_begin_; b < n_; ++b) {
    if (b == i) continue;
    Vec3<Real> d{soa_x_[i] - soa_x_[b], soa_y_[i] - soa_y_[b], soa_z_[i] - soa_z_[b]};
    for (int a = 0; a < 3; ++a)
      if (box.periodic[a]) d[a] -= std::nearbyint(d[a] / g_.length[a]) * g_.length[a];
    const Real gap = std::sqrt(dot(d, d)) - (radius_[i] + radius_[b]);
    if (gap >= gap_lo && gap < gap_hi) push(b, gap);
  }
}

}  // namespace hardsphere::detail
