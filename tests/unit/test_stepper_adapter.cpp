// The stepper's adapter API (what the CLI, Python and LAMMPS call): scatter, gather, copy and set
// of every field, per-sphere virials, the kinetic-energy sum, wrap counts, set_spheres and the
// rebuild agreement.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <tuple>
#include <utility>

#include "hardsphere/errors.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/state_exchange.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

using test::binary_mixture_with_walls;
using test::gas;
using test::two;

}  // namespace

TEST(StepperAdapterApi, ScatterSkipsNoRowSlotsAndCopiesChosenVelocities) {
  // An adapter writes back only the spheres it owns (kNoRow for the others) and reads the
  // velocities of chosen slots, e.g. the copies it compares with their owners.
  const auto s = two({1, 2, 3}, {0.5, 0, 0}, {5, 6, 7}, {0, -0.25, 0});
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(s, {}, cfg);
  st->run(10);
  auto& ex = hardsphere::state_exchange(*st);
  std::vector<std::int64_t> ids(2);
  ex.copy_ids(ids.data());
  const std::size_t first = ids[0] == 1 ? 0 : 1;  // the slot of id 1
  std::vector<std::uint32_t> dest(2, hardsphere::StateExchange::kNoRow);
  dest[first] = 0;
  std::vector<double> x(6, -1.0), v(6, -1.0);
  const std::vector<Vec3d> shift(2, Vec3d{0, 0, 0});
  ex.scatter_state(dest.data(), shift.data(), x.data(), v.data());
  EXPECT_NEAR(x[0], 1.05, 1e-12);
  EXPECT_EQ(v[0], 0.5);
  for (std::size_t i = 3; i < 6; ++i) EXPECT_EQ(x[i], -1.0) << "a kNoRow slot was written";
  const std::uint32_t other = std::uint32_t(1 - first);
  Vec3d u{};
  ex.copy(hardsphere::SphereField::Velocity, &other, 1, &u);
  EXPECT_EQ(u.x, 0.0);
  EXPECT_EQ(u.y, -0.25);
}

TEST(StepperAdapterApi, SphereVirialGivesEachSphereHalfOfItsCollisions) {
  // The oblique impact above: r (x) dp has 1/(2 sqrt(2)) in xx, yy and xy; each sphere takes half.
  const double h = 1 / std::sqrt(2.0);
  const auto s = two({5 - 0.5 * h - 0.05, 5 - 0.5 * h, 5}, {1, 0, 0}, {5 + 0.5 * h, 5 + 0.5 * h, 5}, {0, 0, 0});
  StepperConfig cfg;
  cfg.dt = 0.2;
  auto st = make_stepper(s, {}, cfg);
  auto& ex = state_exchange(*st);
  ex.set_sphere_virial(true);
  st->run(1);
  ASSERT_EQ(st->counters().collisions, 1);
  const std::vector<std::uint32_t> dest = {0, 1};
  std::vector<double> rows(12, 0.0);
  ex.take_sphere_virial(dest.data(), 2.0, rows.data());  // scaled by 2: the whole tensor per sphere
  const double q = 0.5 * h;
  for (std::size_t a = 0; a < 2; ++a) {
    const double* w = &rows[6 * a];
    EXPECT_NEAR(w[0], q, 1e-12);
    EXPECT_NEAR(w[1], q, 1e-12);
    EXPECT_NEAR(w[3], q, 1e-12);
    EXPECT_NEAR(w[2], 0.0, 1e-15);
    EXPECT_NEAR(w[4], 0.0, 1e-15);
    EXPECT_NEAR(w[5], 0.0, 1e-15);
  }
  // Taken sums are cleared; a later step without collisions adds nothing.
  std::fill(rows.begin(), rows.end(), 0.0);
  st->run(1);
  ex.take_sphere_virial(dest.data(), 1.0, rows.data());
  for (const double w : rows) EXPECT_EQ(w, 0.0);
}

TEST(StepperAdapterApi, SphereVirialFollowsTheSpheresThroughRebuilds) {
  // A gas over 210 steps (many cell re-sorts), the sums taken every 7 steps, so the spheres are
  // re-sorted while they hold them: in each piece a sphere that collided has a positive trace
  // (r . dp > 0 for every collision), one that did not has nothing, and the spheres add up to
  // the piece's virial tensor.
  StepperConfig cfg;
  cfg.dt = 0.01;
  cfg.count_per_sphere = true;
  auto st = make_stepper(gas(500, 0.3, 11), {}, cfg);
  auto& ex = state_exchange(*st);
  ex.set_sphere_virial(true);
  const std::size_t n = ex.size();
  std::vector<std::int64_t> ids(n);
  std::vector<std::uint32_t> dest(n);
  std::vector<double> rows(6 * n);
  std::int64_t collided_spheres = 0;
  for (int step = 0; step < 210; step += 7) {
    const std::vector<std::int64_t> before = st->pair_collisions_per_sphere();
    const std::array<double, 6> t0 = st->counters().pair_virial_tensor;
    st->run(7);
    const std::vector<std::int64_t> after = st->pair_collisions_per_sphere();
    ex.copy_ids(ids.data());
    for (std::size_t k = 0; k < n; ++k) dest[k] = std::uint32_t(ids[k] - 1);  // row = id order, like state()
    std::fill(rows.begin(), rows.end(), 0.0);
    ex.take_sphere_virial(dest.data(), 1.0, rows.data());
    for (std::size_t c = 0; c < 6; ++c) {
      double sum = 0;
      for (std::size_t a = 0; a < n; ++a) sum += rows[6 * a + c];
      const double expect = st->counters().pair_virial_tensor[c] - t0[c];
      EXPECT_NEAR(sum, expect, 1e-9 * (1 + std::abs(expect))) << "step " << step << " component " << c;
    }
    for (std::size_t a = 0; a < n; ++a) {
      const double* w = &rows[6 * a];
      if (after[a] > before[a]) {
        ++collided_spheres;
        EXPECT_GT(w[0] + w[1] + w[2], 0.0) << "step " << step << " sphere " << a;
      } else {
        for (std::size_t c = 0; c < 6; ++c) ASSERT_EQ(w[c], 0.0) << "step " << step << " sphere " << a;
      }
    }
  }
  EXPECT_GT(st->counters().rebuilds, 10);
  EXPECT_GT(collided_spheres, 1000);
}

TEST(StepperAdapterApi, Mv2SumIsTwiceTheKineticEnergyAsCollisionsAndGravityChangeIt) {
  // Inelastic collisions (equal spheres) and gravity between walls (a mixture) change the kinetic
  // energy inside the steps; the sum an adapter reads each step matches the state's.
  auto cooling = gas(500, 0.2, 7);
  auto mixture = binary_mixture_with_walls(400);
  StepperConfig inelastic, falling;
  Physics inelastic_physics, falling_physics;
  inelastic.dt = falling.dt = 0.01;
  inelastic_physics.restitution = 0.8;
  inelastic_physics.contact_time = 1e-4;
  falling_physics.gravity = {0, 0, -1};
  for (auto [sys, physics, cfg] :
       {std::tuple{cooling, inelastic_physics, inelastic}, std::tuple{mixture, falling_physics, falling}}) {
    auto st = make_stepper(sys, physics, cfg);
    const double before = 2 * kinetic_energy(st->state());
    st->run(50);
    const double after = 2 * kinetic_energy(st->state());
    EXPECT_GT(std::abs(after / before - 1), 1e-3) << "the scene should change its kinetic energy";
    EXPECT_NEAR(hardsphere::state_exchange(*st).mv2_sum(), after, 1e-12 * after);
  }
}

TEST(StepperAdapterApi, WrapCountsKeepTheUnwrappedTrajectoryContinuous) {
  // Two spheres on parallel lines (never touching) cross the periodic faces many times, one
  // forwards in x and backwards in z, the other backwards in y. What an adapter reads back
  // (position + image * L, copy_ids/copy_images/scatter_state in the engine's slot order) must
  // be the straight line x0 + v t.
  const Vec3d x1{1, 2, 3}, v1{3.7, 0, -2.3}, x2{5, 6, 7}, v2{0, -4.1, 0};
  const auto s = two(x1, v1, x2, v2);
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(s, {}, cfg);
  st->run(1000);  // t = 10: 37, 23 and 41 box lengths of 10 travelled
  const std::size_t n = hardsphere::state_exchange(*st).size();
  std::vector<std::int64_t> ids(n);
  std::vector<std::int32_t> img(3 * n);
  std::vector<std::uint32_t> dest{1, 0};  // written in reverse slot order
  std::vector<double> x(3 * n), v(3 * n);
  const std::vector<Vec3d> shift{{10, 0, 0}, {0, 0, -20}};
  hardsphere::state_exchange(*st).copy_ids(ids.data());
  hardsphere::state_exchange(*st).copy_images(img.data());
  hardsphere::state_exchange(*st).scatter_state(dest.data(), shift.data(), x.data(), v.data());
  EXPECT_EQ(st->counters().collisions, 0);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3d x0 = ids[k] == 1 ? x1 : x2, v0 = ids[k] == 1 ? v1 : v2;
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(x[3 * dest[k] + d] - shift[k][d] + 10.0 * img[3 * k + d], x0[d] + 10.0 * v0[d], 1e-9)
          << "id " << ids[k] << " axis " << d;
      EXPECT_EQ(v[3 * dest[k] + d], v0[d]);
    }
  }
}

TEST(StepperAdapterApi, SetSpheresTakesEffectAtTheNextStepHoweverFast) {
  // An adapter moves sphere 2 next to sphere 1 and sends it at it at 500 diameters per unit
  // time: 5 diameters in the next step, far past the skin. The step must be split for the new
  // speed (an unsplit one would jump through sphere 1) and the head-on collision swap the
  // velocities.
  const auto s = two({5, 10, 10}, {0, 0, 0}, {15, 10, 10}, {0, 0.1, 0}, 0.5, 0.5, 1, 1, 20);
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(s, {}, cfg);
  st->run(1);
  auto& ex = state_exchange(*st);
  std::vector<std::int64_t> ids(2);
  ex.copy_ids(ids.data());
  const std::uint32_t slot2 = ids[0] == 2 ? 0 : 1;
  const Vec3d pos{8, 10, 10}, vel{-500, 0, 0};
  ex.set(hardsphere::SphereField::Position, &slot2, 1, &pos);
  ex.set(hardsphere::SphereField::Velocity, &slot2, 1, &vel);
  st->run(1);
  const auto out = st->state();
  EXPECT_EQ(st->counters().collisions, 1);
  EXPECT_GT(st->counters().substeps, 2);  // the second step was split
  EXPECT_NEAR(out.vel[0].x, -500.0, 1e-9);
  EXPECT_NEAR(out.vel[1].x, 0.0, 1e-9);
  EXPECT_NEAR(out.pos[0].x, 2.0, 1e-9);  // sphere 1 leaves at t = 0.004 (gap 2 closed at 500)
  EXPECT_NEAR(out.pos[1].x, 6.0, 1e-9);
}

// Every SphereField, smooth and rough, through the four field-generic calls: scatter writes what
// copy reads, a gather of it leaves the state bit for bit, and copy reads back what set wrote.
TEST(StepperExchange, EveryFieldRoundTripsThroughCopyScatterGatherSet) {
  const ParticleSystem s = gas(300, 0.3, 5);  // box from the origin: positions come back exactly
  Physics rough;
  rough.tangential_restitution = 0.5;
  for (const Physics& physics : {Physics{}, rough})
    for (const SphereField f : {SphereField::Position, SphereField::Velocity, SphereField::Omega}) {
      auto st = make_stepper(s, physics, StepperConfig{});
      st->run(3);
      StateExchange& x = state_exchange(*st);
      const std::size_t n = x.size();
      const ParticleSystem before = st->state();
      std::vector<Vec3d> got(n);
      x.copy(f, nullptr, n, got.data());
      std::vector<std::uint32_t> rows(n);
      for (std::uint32_t k = 0; k < n; ++k) rows[k] = std::uint32_t(n - 1 - k);
      std::vector<double> flat(3 * n, -1);
      x.scatter(f, rows.data(), flat.data());
      for (std::size_t k = 0; k < n; ++k) EXPECT_EQ(flat[3 * rows[k] + 1], got[k].y) << int(f) << " slot " << k;
      x.gather(f, rows.data(), flat.data());
      const ParticleSystem after = st->state();
      for (std::size_t i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) {
          EXPECT_EQ(after.pos[i][d], before.pos[i][d]) << int(f) << " sphere " << i;
          EXPECT_EQ(after.vel[i][d], before.vel[i][d]) << int(f) << " sphere " << i;
          EXPECT_EQ(after.omega[i][d], before.omega[i][d]) << int(f) << " sphere " << i;
        }
      const std::uint32_t slot = 7;
      const Vec3d value = f == SphereField::Position ? got[slot] : Vec3d{0.25, -0.5, 1.0};
      x.set(f, &slot, 1, &value);
      Vec3d back{};
      x.copy(f, &slot, 1, &back);
      EXPECT_EQ(back.x, value.x);
      EXPECT_EQ(back.y, value.y);
      EXPECT_EQ(back.z, value.z);
    }
}

TEST(StepperAdapterApi, RebuildAgreementIsAskedOncePerStepAndCanOnlyAddRebuilds) {
  // Engines on MPI ranks rebuild their pair lists on the steps any of them needs to. The
  // engine asks once per step, also when a long step is split into sub-steps; an answer of
  // "no" cannot skip a rebuild the engine needs, and "yes" rebuilds without changing the run.
  // Runs over t = 2 at most: the gas's chaos keeps rounding differences below 1e-9 there.
  // Steps of 1 move the fastest spheres beyond the skin (at most ~3 diameters here).
  const auto s = gas(200, 0.2, 9);
  for (const double dt : {0.01, 1.0}) {
    StepperConfig cfg;
    cfg.dt = dt;
    const std::int64_t steps = dt < 0.1 ? 100 : 2;
    auto alone = make_stepper(s, {}, cfg), never = make_stepper(s, {}, cfg), always = make_stepper(s, {}, cfg);
    std::int64_t asked_never = 0, asked_always = 0, due_told = 0;
    state_exchange(*never).set_rebuild_agreement([&](bool due) {
      ++asked_never;
      due_told += due ? 1 : 0;
      return false;
    });
    state_exchange(*always).set_rebuild_agreement([&](bool) {
      ++asked_always;
      return true;
    });
    alone->run(steps), never->run(steps), always->run(steps);
    EXPECT_EQ(asked_never, steps) << "dt " << dt;
    EXPECT_EQ(asked_always, steps) << "dt " << dt;
    if (dt > 0.1) {
      EXPECT_GT(never->counters().substeps, 2 * steps) << "the long steps were not split";
    }
    ASSERT_GT(due_told, 0) << "dt " << dt;
    EXPECT_EQ(never->counters().rebuilds, alone->counters().rebuilds) << "dt " << dt;
    EXPECT_GE(always->counters().rebuilds, steps) << "dt " << dt;
    EXPECT_GT(always->counters().rebuilds, alone->counters().rebuilds) << "dt " << dt;
    EXPECT_EQ(always->counters().collisions, alone->counters().collisions) << "dt " << dt;
    const auto a = alone->state(), b = never->state(), c = always->state();
    for (std::size_t i = 0; i < s.size(); ++i) {
      ASSERT_EQ(a.pos[i].x, b.pos[i].x);
      ASSERT_EQ(a.vel[i].y, b.vel[i].y);
      EXPECT_NEAR(a.pos[i].z, c.pos[i].z, 1e-9);
      EXPECT_NEAR(a.vel[i].x, c.vel[i].x, 1e-9);
    }
  }
}
