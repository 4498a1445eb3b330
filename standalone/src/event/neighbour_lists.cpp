#include "event/neighbour_lists.hpp"

namespace hardsphere::event {

NeighbourLists::NeighbourLists(const EventGeometry& geo, const std::vector<Centre>& centres, std::size_t nbig)
    : grid_(geo, centres, nbig) {
  const std::size_t n = centres.size();
  big_nbr_.assign(nbig, std::vector<std::uint32_t>(kPerLine));
  mark_.assign(n, 0);
  nfill_.assign(n, 0);
  alloc_lists(nbr_, nbase_, n);
  for (int i = 0; i < int(n); ++i)
    grid_.for_each_in_range(i, centres[std::size_t(i)], [&](int j, std::uint32_t image) {
      if (j < i) return;  // each pair once, entered in both lists
      add_neighbour(i, adj_entry(std::uint32_t(j), std::uint8_t(image)));
      add_neighbour(j, adj_entry(std::uint32_t(i), std::uint8_t(kImages - 1 - image)));
    });
}

void NeighbourLists::alloc_lists(std::vector<std::uint32_t>& v, std::size_t& base, std::size_t n) const {
  v.assign(n * std::size_t(ncap_) + kPerLine, 0);
  const auto addr = reinterpret_cast<std::uintptr_t>(v.data());
  base = ((64 - addr % 64) % 64) / sizeof(std::uint32_t);
}

void NeighbourLists::grow_lists() {
  const int old = ncap_;
  ncap_ *= 2;
  std::vector<std::uint32_t> s;
  std::size_t base = 0;
  alloc_lists(s, base, std::size_t(grid_.small_count()));
  for (std::size_t i = 0; i < std::size_t(grid_.small_count()); ++i)
    std::copy_n(&nbr_[nbase_ + i * std::size_t(old)], nfill_[i], &s[base + i * std::size_t(ncap_)]);
  nbr_.swap(s);
  nbase_ = base;
}

void NeighbourLists::permute(const Renumbering& r) {
  grid_.permute(r);
  r.permute(mark_);
  const std::size_t n = r.size(), nsmall = std::size_t(grid_.small_count());
  std::vector<std::uint32_t> lists;
  std::size_t base = 0;
  alloc_lists(lists, base, nsmall);
  std::vector<int> fills(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t o = std::size_t(r.old_of(k));
    fills[k] = nfill_[o];
    const bool big = k >= nsmall;  // big spheres keep their indices and lists
    const std::uint32_t* from = big ? big_nbr_[k - nsmall].data() : &nbr_[nbase_ + o * std::size_t(ncap_)];
    std::uint32_t* to = big ? big_nbr_[k - nsmall].data() : &lists[base + k * std::size_t(ncap_)];
    for (int u = 0; u < nfill_[o]; ++u)
      to[u] = adj_entry(std::uint32_t(r.new_of(adj_partner(from[u]))), adj_image(from[u]));
  }
  nbr_.swap(lists);
  nbase_ = base;
  nfill_.swap(fills);
}

}  // namespace hardsphere::event
