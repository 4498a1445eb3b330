// The resolver's bucket queue of in-step contacts against a binary heap with the same order:
// pushes interleaved with pops, back times that only move earlier-to-later as in a step (most of
// them) but also exact ties, ties broken by a second key, times at both ends of the step, and
// entries pushed above the current front (never produced by the resolver, handled anyway).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "stepper/contact_queue.hpp"

namespace {

struct Entry {
  double back;
  std::uint32_t key;
};
// x comes after y: smaller back (later in the step), ties by larger key
bool later(const Entry& x, const Entry& y) { return x.back != y.back ? x.back < y.back : x.key > y.key; }

void run(std::uint64_t seed, double dt, bool only_later_pushes) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  hardsphere::ContactQueue<Entry, double> q;
  q.reset(dt);
  std::vector<Entry> heap;
  auto cmp = [](const Entry& x, const Entry& y) { return later(x, y); };
  double front = dt;  // the latest popped back time: what the resolver's pushes stay below
  std::uint32_t key = 0;
  std::size_t popped = 0;
  for (int round = 0; round < 4000; ++round) {
    const int pushes = int(u(rng) * 4);
    for (int k = 0; k < pushes; ++k) {
      double back = u(rng) < 0.1 ? front : front * u(rng);  // exact ties with the front now and then
      if (u(rng) < 0.05) back = 0.0;
      if (!only_later_pushes && u(rng) < 0.05) back = dt * u(rng);  // above the front
      const Entry e{back, key++ % 97};                              // repeated keys: ties on both fields are possible
      q.push(e, cmp);
      heap.push_back(e);
      std::push_heap(heap.begin(), heap.end(), cmp);
    }
    ASSERT_EQ(q.size(), heap.size());
    if (!heap.empty() && u(rng) < 0.7) {
      ASSERT_EQ(q.top().back, heap.front().back);
      ASSERT_EQ(q.top().key, heap.front().key);
      const Entry e = q.pop(cmp);
      std::pop_heap(heap.begin(), heap.end(), cmp);
      const Entry want = heap.back();
      heap.pop_back();
      ASSERT_EQ(e.back, want.back) << "pop " << popped;
      ASSERT_EQ(e.key, want.key) << "pop " << popped;
      front = e.back;
      ++popped;
    }
  }
  while (!heap.empty()) {  // drain
    const Entry e = q.pop(cmp);
    std::pop_heap(heap.begin(), heap.end(), cmp);
    ASSERT_EQ(e.back, heap.back().back);
    ASSERT_EQ(e.key, heap.back().key);
    heap.pop_back();
  }
  EXPECT_TRUE(q.empty());
  EXPECT_GT(popped, 2000u);
  q.reset(dt);  // reusable after a reset
  q.push({0.5 * dt, 1}, cmp);
  EXPECT_EQ(q.pop(cmp).key, 1u);
}

}  // namespace

TEST(ContactQueue, MatchesAHeapForInStepPushes) { run(1, 0.01, true); }
TEST(ContactQueue, MatchesAHeapWithPushesAboveTheFront) { run(2, 0.02, false); }
TEST(ContactQueue, MatchesAHeapForAUnitStep) { run(3, 1.0, true); }
