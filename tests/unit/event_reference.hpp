#pragma once
// A textbook all-pairs event-driven reference and the collision-by-collision comparison of the
// event engine with it, shared by the event engine's tests.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hardsphere/collision.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/particles.hpp"

namespace hardsphere::test {

//! Reference for the neighbour lists: a textbook event-driven simulation in which every prediction
//! examines every other sphere (all pairs, nearest periodic image) and every wall, and all spheres
//! are advanced together. After an event the spheres involved, and every sphere that had predicted
//! a collision with one of them, are predicted again (Alder and Wainwright's table). A prediction
//! looks only as far ahead as no other periodic image of a partner can come into contact (the
//! horizon); a sphere reaching its horizon is simply predicted again.
struct ReferenceEdmd {
  ParticleSystem s;
  bool mono;
  double t = 0;
  std::vector<double> when;  // absolute time of each sphere's next event
  std::vector<int> partner;  // >= 0: pair collision; -1 - axis: wall; kHorizon: look again
  std::int64_t collisions = 0, walls = 0;
  double virial = 0;
  static constexpr int kHorizon = -100;

  explicit ReferenceEdmd(const ParticleSystem& init) : s(init), mono(init.monodisperse()) {
    when.assign(s.size(), 0);
    partner.assign(s.size(), kHorizon);
    for (std::size_t i = 0; i < s.size(); ++i) predict(i);
  }
  Vec3d image(Vec3d d) const {
    for (int k = 0; k < 3; ++k)
      if (s.box.periodic[k]) d[k] -= s.box.length(k) * std::nearbyint(d[k] / s.box.length(k));
    return d;
  }
  //! The largest contact distance of any pair: the two largest radii.
  double largest_contact() const {
    double r1 = 0, r2 = 0;
    for (double r : s.radius)
      if (r > r1)
        r2 = r1, r1 = r;
      else if (r > r2)
        r2 = r;
    return r1 + r2;
  }
  void predict(std::size_t i) {
    double vmax = 0, half = kernel::never<double>();
    for (const auto& v : s.vel) vmax = std::max(vmax, norm(v));
    for (int k = 0; k < 3; ++k)
      if (s.box.periodic[k]) half = std::min(half, s.box.length(k) / 2);
    double best = (half - largest_contact()) / (norm(s.vel[i]) + vmax);
    int who = kHorizon;
    for (std::size_t j = 0; j < s.size(); ++j) {
      if (j == i) continue;
      const double tc =
          kernel::contact_time(image(s.pos[i] - s.pos[j]), s.vel[i] - s.vel[j], s.radius[i] + s.radius[j]);
      if (tc < best) best = tc, who = int(j);
    }
    for (int d = 0; d < 3; ++d) {
      if (s.box.periodic[d]) continue;
      double tw = kernel::never<double>();
      if (s.vel[i][d] > 0) tw = (s.box.hi[d] - s.radius[i] - s.pos[i][d]) / s.vel[i][d];
      if (s.vel[i][d] < 0) tw = (s.box.lo[d] + s.radius[i] - s.pos[i][d]) / s.vel[i][d];
      if (tw < best) best = std::max(tw, 0.0), who = -1 - d;
    }
    when[i] = t + best;
    partner[i] = who;
  }
  void run_until(double t_end) {
    for (;;) {
      const std::size_t a = std::size_t(std::min_element(when.begin(), when.end()) - when.begin());
      if (when[a] > t_end) break;
      const double dt = when[a] - t;
      for (std::size_t i = 0; i < s.size(); ++i) s.pos[i] += dt * s.vel[i];
      t = when[a];
      const int b = partner[a];
      if (b == kHorizon) {
        predict(a);
        continue;
      }
      if (b < 0) {
        s.vel[a][-1 - b] = -s.vel[a][-1 - b];
        ++walls;
      } else {
        const Vec3d dr = image(s.pos[a] - s.pos[std::size_t(b)]);
        virial += mono ? s.mass[a] * kernel::collide_equal_mass(dr, s.vel[a], s.vel[std::size_t(b)])
                       : kernel::collide(dr, s.vel[a], s.vel[std::size_t(b)], s.mass[a], s.mass[std::size_t(b)]);
        ++collisions;
      }
      for (std::size_t i = 0; i < s.size(); ++i)
        if (i == a || int(i) == b || partner[i] == int(a) || (b >= 0 && partner[i] == b)) predict(i);
    }
    for (std::size_t i = 0; i < s.size(); ++i) s.pos[i] += (t_end - t) * s.vel[i];
    t = t_end;
  }
};

//! Runs the engine and the reference side by side: the same number of collisions and wall
//! bounces at every checkpoint, and the same state and virial at the end.
inline void expect_same_as_reference(const ParticleSystem& init, const EventConfig& cfg, double t_end, int checkpoints,
                                     std::int64_t min_collisions) {
  ReferenceEdmd ref(init);
  EventEngine e(init, {}, cfg);
  for (int k = 1; k <= checkpoints; ++k) {
    const double tk = t_end * k / checkpoints;
    ref.run_until(tk);
    e.advance(tk - e.time());
    ASSERT_EQ(e.counters().collisions, ref.collisions) << "at t = " << tk << ", shell " << cfg.shell;
    ASSERT_EQ(e.counters().wall_collisions, ref.walls) << "at t = " << tk << ", shell " << cfg.shell;
  }
  EXPECT_GT(ref.collisions, min_collisions);
  EXPECT_NEAR(e.counters().pair_virial, ref.virial, 1e-9 * ref.virial);
  const auto out = e.state();
  double worst = 0;
  for (std::size_t i = 0; i < init.size(); ++i)
    worst = std::max({worst, norm(ref.image(out.pos[i] - ref.s.pos[i])), norm(out.vel[i] - ref.s.vel[i])});
  EXPECT_LT(worst, 1e-9) << "shell " << cfg.shell << ", reach " << cfg.reach;
}

}  // namespace hardsphere::test
