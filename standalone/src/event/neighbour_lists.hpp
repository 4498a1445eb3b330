#pragma once
//! The event-driven engine's neighbour lists: each sphere lists every sphere whose list centre
//! is closer than sigma_ij + shell to its own. Symmetric: j is in i's list iff i is in j's. A
//! sphere rebuilds its list when it has moved shell/2 from its centre, so while neither of two
//! unlisted spheres has rebuilt they are more than sigma_ij apart: every collision is between
//! listed spheres. The members are found in the grid of list centres (centre_grid.hpp).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/always_inline.hpp"
#include "common/neighbour_entry.hpp"
#include "event/centre_grid.hpp"
#include "event/geometry.hpp"
#include "event/renumbering.hpp"

namespace hardsphere::event {

class NeighbourLists {
 public:
  NeighbourLists() = default;
  //! The lists of spheres 0..n-1 with these list centres; the last nbig are the big ones.
  NeighbourLists(const EventGeometry& geo, const std::vector<Centre>& centres, std::size_t nbig);

  //! Sphere i's list: entries adj_entry(j, image) (neighbour_entry.hpp, image codes as in
  //! geometry.hpp).
  const std::uint32_t* entries(int i) const {
    return is_big(i) ? big_nbr_[std::size_t(i - grid_.small_count())].data()
                     : &nbr_[nbase_ + std::size_t(i) * std::size_t(ncap_)];
  }
  int size(int i) const { return nfill_[std::size_t(i)]; }
  //! Requests sphere i's list.
  HS_ALWAYS_INLINE void prefetch(int i) const {
    __builtin_prefetch(entries(i));
    __builtin_prefetch(&nfill_[std::size_t(i)]);
  }

  //! Sphere i's list centre is now c (its position, wrapped into the box; `wrapped` if that
  //! moved it): new list, and the symmetric update of the lists it joins or leaves. Returns the
  //! entries new to i's list, valid until the next rebuild.
  const std::vector<std::uint32_t>& rebuild(int i, const Centre& c, bool wrapped) {
    grid_.move(i, c);
    // Old members are marked `was`; those found again become `kept`; the rest leave.
    const std::uint64_t was = ++stamp_, kept = ++stamp_;
    old_list_.assign(list(i), list(i) + nfill_[std::size_t(i)]);
    for (std::uint32_t e : old_list_) mark_[adj_partner(e)] = was;
    nfill_[std::size_t(i)] = 0;
    fresh_.clear();
    grid_.for_each_in_range(i, c, [&](int j, std::uint32_t image) {
      const std::uint32_t entry = adj_entry(std::uint32_t(j), std::uint8_t(image));
      const std::uint32_t back = adj_entry(std::uint32_t(i), std::uint8_t(kImages - 1 - image));
      add_neighbour(i, entry);
      if (mark_[std::size_t(j)] == was) {
        mark_[std::size_t(j)] = kept;
        if (wrapped) reimage_neighbour(j, i, adj_image(back));
      } else {
        add_neighbour(j, back);
        fresh_.push_back(entry);
      }
    });
    for (std::uint32_t e : old_list_)
      if (mark_[adj_partner(e)] == was) remove_neighbour(int(adj_partner(e)), i);
    return fresh_;
  }

  //! An order of the spheres in which spheres close in space are close in memory.
  std::vector<int> locality_order() const { return grid_.locality_order(); }
  void permute(const Renumbering& r);

 private:
  //! Neighbour lists start on cache-line boundaries, so a list of up to 16 entries is one line.
  static constexpr std::size_t kPerLine = 64 / sizeof(std::uint32_t);

  bool is_big(int i) const { return grid_.is_big(i); }
  std::uint32_t* list(int i) {
    return is_big(i) ? big_nbr_[std::size_t(i - grid_.small_count())].data()
                     : &nbr_[nbase_ + std::size_t(i) * std::size_t(ncap_)];
  }
  //! Storage for n lists of capacity ncap_ (a multiple of kPerLine), each on a line boundary.
  void alloc_lists(std::vector<std::uint32_t>& v, std::size_t& base, std::size_t n) const;
  void grow_lists();
  void add_neighbour(int i, std::uint32_t entry) {
    if (is_big(i)) {
      auto& v = big_nbr_[std::size_t(i - grid_.small_count())];
      if (std::size_t(nfill_[std::size_t(i)]) == v.size()) v.resize(std::max<std::size_t>(kPerLine, 2 * v.size()));
    } else if (nfill_[std::size_t(i)] == ncap_) {
      grow_lists();
    }
    list(i)[nfill_[std::size_t(i)]++] = entry;
  }
  //! Removes j from i's list (swap with the last entry; order does not matter).
  void remove_neighbour(int i, int j) {
    std::uint32_t* l = list(i);
    int& f = nfill_[std::size_t(i)];
    for (int u = 0; u < f; ++u)
      if (int(adj_partner(l[u])) == j) {
        l[u] = l[--f];
        return;
      }
  }
  //! Rewrites the image code of j in i's list (j was wrapped back into the box).
  void reimage_neighbour(int i, int j, std::uint32_t image) {
    std::uint32_t* l = list(i);
    for (int u = 0; u < nfill_[std::size_t(i)]; ++u)
      if (int(adj_partner(l[u])) == j) {
        l[u] = adj_entry(std::uint32_t(j), std::uint8_t(image));
        return;
      }
  }

  CentreGrid grid_;
  // Sphere i (not big) holds nbr_[nbase_ + i * ncap_ .. + nfill_[i]) (grown on overflow);
  // nbase_ aligns the lists to cache lines.
  std::vector<std::uint32_t> nbr_;
  std::size_t nbase_ = 0;
  std::vector<int> nfill_;
  int ncap_ = 16;
  std::vector<std::vector<std::uint32_t>> big_nbr_;  // the big spheres' lists, long and sized one by one
  std::vector<std::uint64_t> mark_;                  // rebuild bookkeeping: stamp of the last rebuild that saw j
  std::uint64_t stamp_ = 0;
  std::vector<std::uint32_t> old_list_, fresh_;  // rebuild buffers
};

}  // namespace hardsphere::event
