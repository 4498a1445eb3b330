// The shared contact resolver takes contacts earliest first, ties by atom ids: many independent
// head-on pairs with known contact times (clustered within a bucket's width, and exact ties) must
// collide in exactly that order, whatever order the scan handed them over in. And its neighbour
// sweeps find the contacts a collision causes later in the same step: chains A -> B -> C where
// only A-B is handed over, with B's list padded by distant spheres so C sits at every position
// of rows of 2..10 entries (the vector filter's groups of four and their tails).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "stepper/contact_resolver.hpp"

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
  bool rescan(double) { return true; }
};

TEST(ContactResolver, TakesContactsEarliestFirstWithTiesByAtomIds) {
  const std::uint32_t pairs = 300;
  const double dt = 0.01, u = 1.0;  // closing speed 2u
  std::vector<double> back(pairs);
  for (std::uint32_t p = 0; p < pairs; ++p) {
    if (p < 100)
      back[p] = dt * (0.1 + 0.8 * ((p * 37) % 100) / 100.0);  // spread over the step
    else if (p < 200)
      back[p] = dt * (0.5 + 1e-7 * double(p % 17));  // 17 times inside one bucket
    else
      back[p] = back[p - 200];  // exact ties with the first 100
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

//! Chains A -> B -> C along x: A hits B (at rest) `b1` before the end of the step, B then
//! closes the gap g = f u b1 to C; f < 1 collides within the step, found only by B's sweep.
template <class Real>
void check_chains(bool speeds) {
  const Real dt = Real(0.01), u = Real(1), b1 = Real(0.8) * dt;
  const Real fractions[4] = {Real(0.2), Real(0.55), Real(0.97), Real(1.2)};
  const std::uint32_t chains = 96, max_decoys = 8;
  std::vector<Vec3<Real>> pos, vel;
  std::vector<std::vector<std::uint32_t>> rows;
  std::vector<std::uint32_t> b_of(chains), c_of(chains);
  std::int64_t expected = 0;
  auto add = [&](Vec3<Real> p, Vec3<Real> v) {
    pos.push_back(p), vel.push_back(v), rows.emplace_back();
    return std::uint32_t(pos.size() - 1);
  };
  for (std::uint32_t c = 0; c < chains; ++c) {
    const Real f = fractions[c % 4], y = Real(10) * Real(c), xb = Real(100);
    const std::uint32_t a = add({xb - (Real(1) - u * b1), y, 0}, {u, 0, 0});  // overlapping B: touched b1 ago
    const std::uint32_t b = add({xb, y, 0}, {0, 0, 0});
    const std::uint32_t cc = add({xb + Real(1) + f * u * b1, y, 0}, {0, 0, 0});
    b_of[c] = b, c_of[c] = cc;
    expected += f < Real(1) ? 2 : 1;
    // B's row: A, C at position `at`, and distant spheres (beyond any reach) around them
    const std::uint32_t decoys = (c / 4) % (max_decoys + 1), len = decoys + 2, at = (c / 3) % len;
    std::vector<std::uint32_t> row;
    for (std::uint32_t k = 0; k < decoys; ++k) {
      const std::uint32_t d = add({xb + Real(k), y + Real(4), 0}, {0, u, 0});  // moving away in +y
      row.push_back(d);
      rows[d].push_back(b);
    }
    row.insert(row.begin() + std::min<std::size_t>(row.size(), (at + 1) % len), a);
    row.insert(row.begin() + std::min<std::size_t>(row.size(), at), cc);
    rows[b] = row;
    rows[a].push_back(b);
    rows[cc].push_back(b);
  }
  const std::uint32_t n = std::uint32_t(pos.size());
  std::vector<std::uint32_t> adj_start(n + 1, 0), adj;
  for (std::uint32_t i = 0; i < n; ++i) {
    for (const std::uint32_t q : rows[i]) adj.push_back(hardsphere::adj_entry(q, hardsphere::kNoImage));
    adj_start[i + 1] = std::uint32_t(adj.size());
  }
  std::vector<Real> radius(n, Real(0.5)), mass(n, Real(1)), speed(n);
  for (std::uint32_t i = 0; i < n; ++i) speed[i] = std::sqrt(hardsphere::dot(vel[i], vel[i]));
  std::vector<std::int64_t> id(n);
  for (std::uint32_t i = 0; i < n; ++i) id[i] = i;
  const std::vector<Vec3<Real>> shift(27, Vec3<Real>{0, 0, 0});

  ContactResolver<Real, true> res;
  res.reset(n, dt);
  res.set_uniform(Real(1), Real(1));
  res.set_speed_bound(u);
  res.bind({pos.data(), vel.data(), radius.data(), mass.data(), id.data(), nullptr, adj_start.data(), adj.data(),
            shift.data(), speeds ? speed.data() : nullptr, adj_start.data() + 1});
  for (std::uint32_t c = 0; c < chains; ++c) {
    const std::uint32_t b = b_of[c], a = b - 1;
    res.consider(a, b, hardsphere::kNoImage, pos[a] - pos[b], Real(1), true);
  }
  Recorder rec;
  hardsphere::ContactTally tally;
  res.resolve(rec, tally);
  EXPECT_EQ(tally.collisions, expected);
  for (std::uint32_t c = 0; c < chains; ++c) {  // u passes down the chain as far as it got
    const bool reached = fractions[c % 4] < Real(1);
    EXPECT_EQ(vel[c_of[c]].x, reached ? u : Real(0)) << "chain " << c;
    EXPECT_EQ(vel[b_of[c]].x, reached ? Real(0) : u) << "chain " << c;
  }
}

}  // namespace

TEST(ContactResolver, SweepsFindTheContactsACollisionCausesFloat) { check_chains<float>(true); }
TEST(ContactResolver, SweepsFindTheContactsACollisionCausesFloatNoSpeeds) { check_chains<float>(false); }
TEST(ContactResolver, SweepsFindTheContactsACollisionCausesDouble) { check_chains<double>(true); }
