#pragma once
//! Event calendar of the event-driven engine: each sphere's next event time, earliest first.
//!
//! Spheres are grouped in blocks of 32 consecutive indices (the engine numbers spheres along a
//! space-filling curve, so a block is a patch of space). The keys sit in one flat array, a block
//! in four adjacent cache lines, and an indexed 4-ary min-heap orders the blocks by their
//! earliest key and remembers which sphere holds it. Why not one heap entry per sphere: in large
//! systems that heap misses the caches on each of its lower levels, one dependent miss per level,
//! and walking it dominated a collision's own time. The block heap is 1/32 of its size (mostly in
//! L2); an update reads one block (misses that do not depend on each other, requested early by
//! prefetch()) and touches the heap only when the block's earliest key changes. 32 is the block
//! size that timed best (docs/event_engine.md).
//!
//! Heap layout: the root is at slot 3; the children of slot p are slots 4p-8 .. 4p-5; the
//! parent of slot c is c/4 + 2 (slots 0-2 unused).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/always_inline.hpp"

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace hardsphere {

class EventCalendar {
 public:
  static constexpr std::size_t kBlock = 32;

  //! One entry per index 0..n-1 with the given keys.
  void build(const std::vector<double>& keys) {
    const std::size_t n = keys.size(), blocks = (n + kBlock - 1) / kBlock;
    storage_.assign(blocks * kBlock + kAlign, std::numeric_limits<double>::infinity());
    const auto addr = reinterpret_cast<std::uintptr_t>(storage_.data());
    base_ = ((64 - addr % 64) % 64) / sizeof(double);
    for (std::size_t i = 0; i < n; ++i) keys_()[i] = keys[i];
    node_.assign(blocks + kRoot, Node{0, 0, 0});
    where_.resize(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
      node_[b + kRoot] = block_min(std::uint32_t(b));
      where_[b] = std::uint32_t(b + kRoot);
    }
    for (std::size_t p = node_.size(); p-- > kRoot;) sift_down(p);
  }
  bool empty() const { return node_.size() <= kRoot; }
  //! The sphere with the earliest key (of equal keys, the one its block recorded).
  std::uint32_t top() const { return node_[kRoot].arg; }
  double top_key() const { return node_[kRoot].key; }
  double key(std::uint32_t i) const { return keys_()[i]; }

  //! Earliest sphere of the k-th child (0..3) of the root block, or -1 (as unsigned) if there is
  //! none: likely events after the top's.
  std::uint32_t runner_up(int k) const {
    const std::size_t p = 4 * kRoot - 8 + std::size_t(k);
    return p < node_.size() ? node_[p].arg : std::uint32_t(-1);
  }
  //! Requests what an update of entry i reads (to overlap the cache misses).
  HS_ALWAYS_INLINE void prefetch(std::uint32_t i) const {
    const double* k = keys_() + std::size_t(i / kBlock) * kBlock;
    for (std::size_t s = 0; s < kBlock; s += 8) __builtin_prefetch(k + s);
    __builtin_prefetch(&where_[i / kBlock]);
  }
  //! Changes the key of entry i and restores the order.
  void update(std::uint32_t i, double key) {
    keys_()[i] = key;
    const std::uint32_t b = i / kBlock;
    const std::size_t p = where_[b];
    Node& nd = node_[p];
    if (key < nd.key) {  // i is now its block's earliest
      nd.key = key;
      nd.arg = i;
      sift_up(p);
    } else if (nd.arg == i) {  // the block's earliest moved later: find the new earliest
      nd = block_min(b);
      sift_down(p);
    }  // otherwise the block's earliest is unchanged
  }
  //! Subtracts `shift` from every key (order is kept: rounding is monotone).
  void shift_keys(double shift) {
    double* k = keys_();
    for (std::size_t i = 0; i < where_.size() * kBlock; ++i) k[i] -= shift;
    for (std::size_t p = kRoot; p < node_.size(); ++p) node_[p].key -= shift;
  }

 private:
  static constexpr std::size_t kRoot = 3;
  static constexpr std::size_t kAlign = 64 / sizeof(double);  // spare keys for the alignment
  struct Node {
    double key;         // the block's earliest key
    std::uint32_t blk;  // the block
    std::uint32_t arg;  // the sphere holding that key
  };
  //! The earliest key of block b and the lowest index holding it (an all-infinite block
  //! names its first sphere, which exists: padding only fills the end of the last block).
  Node block_min(std::uint32_t b) const {
    const double* k = keys_() + std::size_t(b) * kBlock;
#if defined(__AVX__)
    static_assert(kBlock % 8 == 0 && kBlock <= 64);
    __m256d m4 = _mm256_min_pd(_mm256_loadu_pd(k), _mm256_loadu_pd(k + 4));
    for (std::size_t s = 8; s < kBlock; s += 4) m4 = _mm256_min_pd(m4, _mm256_loadu_pd(k + s));
    const __m128d m2 = _mm_min_pd(_mm256_castpd256_pd128(m4), _mm256_extractf128_pd(m4, 1));
    const double m = _mm_cvtsd_f64(_mm_min_sd(m2, _mm_unpackhi_pd(m2, m2)));
    const __m256d mm = _mm256_set1_pd(m);
    std::uint64_t at = 0;
    for (std::size_t s = 0; s < kBlock; s += 4)
      at |= std::uint64_t(_mm256_movemask_pd(_mm256_cmp_pd(_mm256_loadu_pd(k + s), mm, _CMP_EQ_OQ))) << s;
    const std::uint32_t a = at ? std::uint32_t(__builtin_ctzll(at)) : 0;  // at == 0 only for a NaN key
#else
    double m = k[0];
    for (std::size_t s = 1; s < kBlock; ++s) m = k[s] < m ? k[s] : m;
    std::uint32_t a = 0;
    while (a + 1 < kBlock && !(k[a] <= m)) ++a;
#endif
    return {m, b, b * std::uint32_t(kBlock) + a};
  }
  void sift_up(std::size_t p) {
    const Node x = node_[p];
    while (p > kRoot) {
      const std::size_t q = p / 4 + 2;
      if (!(x.key < node_[q].key)) break;
      node_[p] = node_[q];
      where_[node_[p].blk] = std::uint32_t(p);
      p = q;
    }
    node_[p] = x;
    where_[x.blk] = std::uint32_t(p);
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
      where_[node_[p].blk] = std::uint32_t(p);
      p = c;
    }
    node_[p] = x;
    where_[x.blk] = std::uint32_t(p);
  }

  std::vector<double> storage_;  // keys, padded with +inf to whole blocks, plus alignment slack
  std::size_t base_ = 0;         // the keys start at storage_[base_], on a 64-byte boundary
  double* keys_() { return storage_.data() + base_; }
  const double* keys_() const { return storage_.data() + base_; }
  std::vector<Node> node_ = std::vector<Node>(kRoot, Node{0, 0, 0});
  std::vector<std::uint32_t> where_;  // heap slot of each block
};

}  // namespace hardsphere
