#pragma once
//! Event calendar of the event-driven engine: an indexed 4-ary min-heap with exactly one entry
//! per sphere, keyed by that sphere's next event time. Keys sit next to the indices in the heap
//! array, and the four children of a node are adjacent (64 bytes, at most two cache lines), so a
//! sift touches about half as many lines as a binary heap; `where` finds a sphere's entry for
//! updates. (64-byte aligned storage, one line per family, measured no gain at N = 10^6.)
//!
//! Layout: the root is at slot 3; the children of slot p are slots 4p-8 .. 4p-5; the parent of
//! slot c is c/4 + 2 (slots 0-2 unused).
#include <cstdint>
#include <vector>

#include "hardsphere/always_inline.hpp"

namespace hardsphere {

class EventCalendar {
 public:
  //! One entry per index 0..n-1 with the given keys.
  void build(const std::vector<double>& keys) {
    const std::size_t n = keys.size();
    node_.assign(n + kRoot, Node{0, 0});
    where_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      node_[i + kRoot] = {keys[i], std::uint32_t(i)};
      where_[i] = std::uint32_t(i + kRoot);
    }
    for (std::size_t p = node_.size(); p-- > kRoot;) sift_down(p);
  }
  bool empty() const { return node_.size() <= kRoot; }
  std::uint32_t top() const { return node_[kRoot].idx; }
  double top_key() const { return node_[kRoot].key; }
  double key(std::uint32_t i) const { return node_[where_[i]].key; }

  //! Index held by the k-th child (0..3) of the root, or -1 (as unsigned) if there is none: the
  //! entries that can become the top after the top's key grows.
  std::uint32_t runner_up(int k) const {
    const std::size_t p = 4 * kRoot - 8 + std::size_t(k);
    return p < node_.size() ? node_[p].idx : std::uint32_t(-1);
  }
  //! Requests the line that locates entry i (before an update, to overlap the cache miss).
  HS_ALWAYS_INLINE void prefetch(std::uint32_t i) const { __builtin_prefetch(&where_[i]); }
  //! Changes the key of entry i and restores the heap order.
  void update(std::uint32_t i, double key) {
    const std::size_t p = where_[i];
    const double old = node_[p].key;
    node_[p].key = key;
    if (key < old) sift_up(p);
    else sift_down(p);
  }
  //! Subtracts `shift` from every key (order is kept: rounding is monotone).
  void shift_keys(double shift) {
    for (std::size_t p = kRoot; p < node_.size(); ++p) node_[p].key -= shift;
  }

 private:
  static constexpr std::size_t kRoot = 3;
  struct Node {
    double key;
    std::uint32_t idx;
  };
  void sift_up(std::size_t p) {
    const Node x = node_[p];
    while (p > kRoot) {
      const std::size_t q = p / 4 + 2;
      if (!(x.key < node_[q].key)) break;
      node_[p] = node_[q];
      where_[node_[p].idx] = std::uint32_t(p);
      p = q;
    }
    node_[p] = x;
    where_[x.idx] = std::uint32_t(p);
  }
  void sift_down(std::size_t p) {
    const std::size_t end = node_.size();
    const Node x = node_[p];
    for (;;) {
      const std::size_t first = 4 * p - 8;
      if (first >= end) break;
      std::size_t c = first;
      const std::size_t last = first + 4 < end ? first + 4 : end;
      for (std::size_t k = first + 1; k < last; ++k)
        if (node_[k].key < node_[c].key) c = k;
      if (!(node_[c].key < x.key)) break;
      node_[p] = node_[c];
      where_[node_[p].idx] = std::uint32_t(p);
      p = c;
    }
    node_[p] = x;
    where_[x.idx] = std::uint32_t(p);
  }

  std::vector<Node> node_ = std::vector<Node>(kRoot, Node{0, 0});
  std::vector<std::uint32_t> where_;
};

}  // namespace hardsphere
