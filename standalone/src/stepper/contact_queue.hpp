#pragma once
//! The contact resolver's queue of contacts predicted inside a step, earliest first. A contact
//! found after a collision never comes before it (its back time is at most the collision's),
//! so the earliest entry only moves later in time: a bucket queue over the step's back times
//! (bucket k holds back in [k, k + 1) dt / kBuckets) with a cursor that only moves down serves
//! it. Within the cursor's bucket the earliest entry is found by the resolver's own order, so
//! entries come out exactly as from a binary heap with that order, which it replaces: most
//! entries are predictions that go stale before their time, and each push and pop of the heap
//! sifted through several levels (see docs/dev/performance.md).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hardsphere {

//! Candidate: has a member `back` (time before the end of the step). The `later` passed to
//! push() and pop(), later(x, y): x comes after y, must be one strict total order (earliest =
//! largest back first).
template <class Candidate, class Real>
class ContactQueue {
 public:
  static constexpr int kBuckets = 512;

  ContactQueue() : bucket_(kBuckets) {}

  //! Empties the queue for a step of length dt.
  void reset(Real dt) {
    for (int k = 0; k <= top_bucket_; ++k) bucket_[std::size_t(k)].clear();
    scale_ = Real(kBuckets) / dt;
    top_bucket_ = -1;
    size_ = 0;
  }
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }

  template <class Later>
  void push(const Candidate& c, const Later& later) {
    const int k = bucket_of(c.back);
    std::vector<Candidate>& b = bucket_[std::size_t(k)];
    b.push_back(c);
    ++size_;
    if (k > top_bucket_) {  // the first entry, or one rounded into a later bucket
      top_bucket_ = k;
      best_ = b.size() - 1;
    } else if (k == top_bucket_ && later(b[best_], c)) {
      best_ = b.size() - 1;
    }
  }
  //! The earliest entry (queue not empty).
  const Candidate& top() const { return bucket_[std::size_t(top_bucket_)][best_]; }
  //! Removes and returns the earliest entry (queue not empty).
  template <class Later>
  Candidate pop(const Later& later) {
    std::vector<Candidate>& b = bucket_[std::size_t(top_bucket_)];
    const Candidate c = b[best_];
    b[best_] = b.back();
    b.pop_back();
    --size_;
    while (top_bucket_ >= 0 && bucket_[std::size_t(top_bucket_)].empty()) --top_bucket_;
    if (top_bucket_ >= 0) find_best(later);
    return c;
  }

 private:
  int bucket_of(Real back) const {
    const Real x = back * scale_;
    return x >= Real(kBuckets) ? kBuckets - 1 : (x > Real(0) ? int(x) : 0);
  }
  template <class Later>
  void find_best(const Later& later) {
    const std::vector<Candidate>& b = bucket_[std::size_t(top_bucket_)];
    best_ = 0;
    for (std::size_t k = 1; k < b.size(); ++k)
      if (later(b[best_], b[k])) best_ = k;
  }

  std::vector<std::vector<Candidate>> bucket_;
  Real scale_ = 1;
  int top_bucket_ = -1;   // highest non-empty bucket (-1: empty); every bucket above is empty
  std::size_t best_ = 0;  // earliest entry of the top bucket
  std::size_t size_ = 0;
};

//! out = in, earliest contact first (the order of std::sort with `earlier`). Contact times
//! spread over the step of length dt, so a bucket pass by time (monotone in `back`, so it never
//! contradicts `earlier`) leaves a handful per bucket for insertion sorts: O(n), where a
//! comparison sort of a dense step's contacts was a visible part of the run (see
//! docs/dev/performance.md). bucket_start and bucket_fill are scratch.
template <class Candidate, class Real, class Earlier>
void order_by_time(const std::vector<Candidate>& in, std::vector<Candidate>& out, Real dt, const Earlier& earlier,
                   std::vector<std::uint32_t>& bucket_start, std::vector<std::uint32_t>& bucket_fill) {
  const std::size_t n = in.size();
  out.resize(n);
  if (n < 32) {
    std::copy(in.begin(), in.end(), out.begin());
    std::sort(out.begin(), out.end(), earlier);
    return;
  }
  const Real scale = Real(n) / dt;
  auto bucket = [&](Real back) {  // larger back (earlier contact) -> lower bucket
    const Real b = std::max(back, Real(0)) * scale;
    return b < Real(n) ? n - 1 - std::size_t(b) : 0;
  };
  bucket_start.assign(n + 1, 0);
  for (const Candidate& c : in) ++bucket_start[bucket(c.back) + 1];
  for (std::size_t b = 0; b < n; ++b) bucket_start[b + 1] += bucket_start[b];
  bucket_fill.assign(bucket_start.begin(), bucket_start.end() - 1);
  for (const Candidate& c : in) out[bucket_fill[bucket(c.back)]++] = c;
  for (std::size_t b = 0; b < n; ++b) {
    const std::uint32_t lo = bucket_start[b], hi = bucket_start[b + 1];
    for (std::uint32_t k = lo + 1; k < hi; ++k) {  // insertion sort: buckets hold ~1
      const Candidate c = out[k];
      std::uint32_t m = k;
      for (; m > lo && earlier(c, out[m - 1]); --m) out[m] = out[m - 1];
      out[m] = c;
    }
  }
}

}  // namespace hardsphere
