#include "event/centre_grid.hpp"

#include <algorithm>
#include <utility>

namespace hardsphere::event {

CentreGrid::CentreGrid(const EventGeometry& geo, const std::vector<Centre>& centres, std::size_t nbig) : geo_(geo) {
  const std::size_t n = centres.size();
  fill_.assign(geo_.cell_count(), 0);
  cap_ = geo_.reach() == 1 ? 8 : 2;
  slots_.assign(fill_.size() * std::size_t(cap_), -1);
  cell_ctr_.assign(fill_.size() * std::size_t(cap_), Centre{0, 0, 0, 0});
  slot_of_.assign(n, 0);
  nsmall_ = int(n - nbig);
  for (auto* v : {&big_x_, &big_y_, &big_z_, &big_r_, &big_gap_}) v->resize(nbig);
  cc_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Centre& c = centres[k];
    cc_[k] = geo_.cell_of(c.x, c.y, c.z);
    if (is_big(int(k)))
      set_big_centre(int(k), c);
    else
      link(int(k), c);
  }
  // Cells in Morton (Z-curve) order of their coordinates, so cells close in space are close in
  // this list.
  std::vector<std::pair<std::uint64_t, int>> key;
  key.reserve(fill_.size());
  const std::array<int, 3>& nc = geo_.cells();
  for (int z = 0; z < nc[2]; ++z)
    for (int y = 0; y < nc[1]; ++y)
      for (int x = 0; x < nc[0]; ++x) {
        std::uint64_t m = 0;
        for (int bit = 0; bit < 21; ++bit)
          m |= (std::uint64_t((x >> bit) & 1) << (3 * bit)) | (std::uint64_t((y >> bit) & 1) << (3 * bit + 1)) |
               (std::uint64_t((z >> bit) & 1) << (3 * bit + 2));
        key.emplace_back(m, geo_.cell_index({x, y, z}));
      }
  std::sort(key.begin(), key.end());
  cell_order_.resize(key.size());
  for (std::size_t k = 0; k < key.size(); ++k) cell_order_[k] = key[k].second;
}

std::vector<std::uint32_t> CentreGrid::filing_order(const EventGeometry& geo, const std::vector<Vec3d>& pos,
                                                    const std::vector<std::uint32_t>& big) {
  const std::size_t n = pos.size();
  std::vector<std::int64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) key[i] = geo.cell_index(geo.cell_of(pos[i].x, pos[i].y, pos[i].z));
  // Big spheres after every cell, in their given order.
  const std::int64_t ncells = std::int64_t(geo.cell_count());
  for (std::size_t b = 0; b < big.size(); ++b) key[big[b]] = ncells + std::int64_t(b);
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(i);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  return order;
}

void CentreGrid::grow() {
  const int old = cap_;
  cap_ *= 2;
  std::vector<int> s(fill_.size() * std::size_t(cap_), -1);
  std::vector<Centre> p(fill_.size() * std::size_t(cap_));
  for (std::size_t h = 0; h < fill_.size(); ++h)
    for (int k = 0; k < fill_[h]; ++k) {
      s[h * std::size_t(cap_) + std::size_t(k)] = slots_[h * std::size_t(old) + std::size_t(k)];
      p[h * std::size_t(cap_) + std::size_t(k)] = cell_ctr_[h * std::size_t(old) + std::size_t(k)];
    }
  slots_.swap(s);
  cell_ctr_.swap(p);
}

std::vector<int> CentreGrid::locality_order() const {
  const std::size_t n = cc_.size();
  std::vector<int> order;
  order.reserve(n);
  for (int h : cell_order_)
    for (int k = 0; k < fill_[std::size_t(h)]; ++k)
      order.push_back(slots_[std::size_t(h) * std::size_t(cap_) + std::size_t(k)]);
  for (std::size_t k = std::size_t(nsmall_); k < n; ++k) order.push_back(int(k));  // big ones stay last
  return order;
}

void CentreGrid::permute(const Renumbering& r) {
  r.permute(cc_);
  r.permute(slot_of_);
  for (std::size_t h = 0; h < fill_.size(); ++h)
    for (int k = 0; k < fill_[h]; ++k) {
      int& x = slots_[h * std::size_t(cap_) + std::size_t(k)];
      x = r.new_of(std::size_t(x));
    }
}

}  // namespace hardsphere::event
