// The shared contact resolver takes contacts earliest first, ties by atom ids: many independent
// head-on pairs with known contact times (clustered within a bucket's width, and exact ties) must
// collide in exactly that order, whatever order the scan handed them over in.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "hardsphere/contact_resolver.hpp"

namespace {

using hardsphere::ContactResolver;
using hardsphere::Vec3;

struct Recorder {
  std::vector<std::uint32_t> order;  // pair index of each collision, in the order resolved
  void after_collision(std::uint32_t k, double) {
    if (k % 2 == 0) order.push_back(k / 2);  // called for both spheres; the lower one names the pair
  }
  void after_bounce(std::uint32_t) {}
  void prefetch(std::uint32_t) const {}
  bool must_rescan() const { return false; }
  void rescan() {}
};

TEST(ContactResolver, TakesContactsEarliestFirstWithTiesByAtomIds) {
  const std::uint32_t pairs = 300;
  const double dt = 0.01, u = 1.0;  // closing speed 2u
  std::vector<double> back(pairs);
  for (std::uint32_t p = 0; p < pairs; ++p) {
    if (p < 100) back[p] = dt * (0.1 + 0.8 * ((p * 37) % 100) / 100.0);  // spread over the step
    else if (p < 200) back[p] = dt * (0.5 + 1e-7 * double(p % 17));     // 17 times inside one bucket
    else back[p] = back[p - 200];                                        // exact ties with the first 100
  }
  const std::uint32_t n = 2 * pairs;
  std::vector<Vec3<double>> pos(n), vel(n);
  std::vector<double> radius(n, 0.5), mass(n, 1.0);
  std::vector<std::int64_t> id(n);
  std::vector<std::uint32_t> adj_start(n + 1), adj(n);
  const std::vector<Vec3<double>> shift(27, Vec3<double>{0, 0, 0});
  for (std::uint32_t p = 0; p < pairs; ++p) {
    const double d = 1.0 - 2.0 * u * back[p];  // separation now: they touched `back` ago
    const std::uint32_t a = 2 * p, b = a + 1;
    // Centres are integers in [1024, 2048): one binade, so equal d gives bit-equal separations
    // (and exact ties) in every pair.
    const double x = 1024.0 + 3.0 * p;
    pos[a] = {x - d / 2, 0, 0}, vel[a] = {u, 0, 0};
    pos[b] = {x + d / 2, 0, 0}, vel[b] = {-u, 0, 0};
    id[a] = 5000 - a, id[b] = 5000 - b;  // ids run against the indices, so ties must use them
    adj[a] = hardsphere::adj_entry(b, hardsphere::kNoImage), adj[b] = hardsphere::adj_entry(a, hardsphere::kNoImage);
  }
  for (std::uint32_t k = 0; k <= n; ++k) adj_start[k] = k;

  ContactResolver<double, true> res;
  res.reset(n, dt);
  res.set_uniform(1.0, 1.0);
  res.bind({pos.data(), vel.data(), radius.data(), mass.data(), id.data(), nullptr, adj_start.data(), adj.data(),
            shift.data()});
  // Handed over in an order unrelated to time.
  for (std::uint32_t q = 0; q < pairs; ++q) {
    const std::uint32_t p = (q * 7) % pairs;
    const std::uint32_t a = 2 * p, b = a + 1;
    res.consider(a, b, hardsphere::kNoImage, pos[a] - pos[b], 1.0, true);
  }
  Recorder rec;
  hardsphere::ContactTally tally;
  res.resolve(rec, tally);

  std::vector<std::uint32_t> expect(pairs);
  for (std::uint32_t p = 0; p < pairs; ++p) expect[p] = p;
  std::sort(expect.begin(), expect.end(), [&](std::uint32_t x, std::uint32_t y) {
    if (back[x] != back[y]) return back[x] > back[y];  // earlier contact = longer ago
    return std::minmax(id[2 * x], id[2 * x + 1]) < std::minmax(id[2 * y], id[2 * y + 1]);
  });
  ASSERT_EQ(tally.collisions, std::int64_t(pairs));
  EXPECT_EQ(rec.order, expect);
  for (std::uint32_t p = 0; p < pairs; ++p) {  // equal masses head-on: the velocities swap
    EXPECT_EQ(vel[2 * p].x, -u);
    EXPECT_EQ(vel[2 * p + 1].x, u);
  }
}

}  // namespace
