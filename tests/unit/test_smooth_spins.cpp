// Smooth spheres keep the angular velocities they were given: no smooth collision changes a spin,
// so every engine hands each sphere's spin back bit for bit, through collisions, wall bounces and
// re-sorts, in both precisions, and data files and dumps carry them (issue 42, item 3).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/rng.hpp"
#include "hardsphere/state_exchange.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

bool same_bits(const Vec3d& a, const Vec3d& b) { return std::memcmp(&a, &b, sizeof(Vec3d)) == 0; }

//! A gas whose spins cover what a file may hold: -0, subnormals, large and small values, zeros.
ParticleSystem spinning(std::int64_t n, double phi, std::array<bool, 3> periodic, bool mixed) {
  ParticleSystem s = test::gas(n, phi, 5, std::nullopt, periodic);
  Rng rng(11);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double scale = i % 4 == 0 ? 1e100 : (i % 4 == 1 ? 1e-300 : 3.0);
    s.omega[i] = {scale * (rng.uniform() - 0.5), scale * (rng.uniform() - 0.5), scale * (rng.uniform() - 0.5)};
    if (mixed && i % 3 == 0) s.radius[i] = 0.35, s.mass[i] = 0.3;
  }
  s.omega[1] = {-0.0, 0.0, std::numeric_limits<double>::denorm_min()};
  s.omega[2] = {0, 0, 0};
  // Input order reversed: the engines sort by id, the spins must follow their spheres.
  ParticleSystem r;
  r.box = s.box;
  for (std::size_t k = s.size(); k-- > 0;)
    r.push_back(s.id[k], s.type[k], s.radius[k], s.mass[k], s.pos[k], s.vel[k], s.image[k], s.omega[k]);
  return r;
}

//! Every sphere of `after` (id order) has the spin its id had in `before`, bit for bit.
void expect_spins_kept(const ParticleSystem& before, const ParticleSystem& after, const std::string& what) {
  ASSERT_EQ(after.omega.size(), before.size()) << what;
  std::size_t checked = 0;
  for (std::size_t k = 0; k < after.size(); ++k)
    for (std::size_t i = 0; i < before.size(); ++i)
      if (before.id[i] == after.id[k]) {
        EXPECT_TRUE(same_bits(before.omega[i], after.omega[k])) << what << ": atom " << after.id[k];
        ++checked;
      }
  EXPECT_EQ(checked, before.size()) << what;
}

}  // namespace

TEST(SmoothSpins, BothEnginesAndPrecisionsKeepThemBitForBit) {
  for (const bool walls : {false, true})
    for (const bool mixed : {false, true}) {
      const ParticleSystem s = spinning(400, 0.3, {true, true, !walls}, mixed);
      const std::string scene = std::string(walls ? "walls" : "periodic") + (mixed ? ", mixed" : "");
      for (const Precision p : {Precision::Double, Precision::Float}) {
        auto st = make_stepper(s, {}, StepperConfig{}, p);
        st->run(300);  // many collisions and list rebuilds (re-sorts)
        EXPECT_GT(st->counters().collisions, 1000);
        expect_spins_kept(s, st->state(), "stepper " + scene + (p == Precision::Float ? ", float" : ""));
      }
      EventEngine ev(s, {}, EventConfig{});
      ev.advance(3.0);
      EXPECT_GT(ev.counters().collisions, 1000);
      expect_spins_kept(s, ev.state(), "event engine " + scene);
      // Inelastic collisions and gravity leave them alone too.
      Physics inelastic;
      inelastic.restitution = 0.7, inelastic.contact_time = 1e-4;
      if (walls) inelastic.gravity = {0, 0, -1};
      auto st2 = make_stepper(s, inelastic, StepperConfig{});
      st2->run(100);
      expect_spins_kept(s, st2->state(), "inelastic stepper " + scene);
      EventEngine ev2(s, inelastic, EventConfig{});
      ev2.advance(1.0);
      expect_spins_kept(s, ev2.state(), "inelastic event engine " + scene);
    }
}

TEST(SmoothSpins, StateExchangeGivesAndTakesThem) {
  const ParticleSystem s = spinning(200, 0.2, {true, true, true}, false);
  auto st = make_stepper(s, {}, StepperConfig{});
  StateExchange& x = state_exchange(*st);
  std::vector<std::uint32_t> slots(x.size()), input(x.size());
  for (std::uint32_t k = 0; k < slots.size(); ++k) slots[k] = k;
  x.copy_input_index(input.data());
  std::vector<Vec3d> w(x.size());
  x.copy(SphereField::Omega, slots.data(), slots.size(), w.data());
  for (std::size_t k = 0; k < w.size(); ++k) EXPECT_TRUE(same_bits(w[k], s.omega[input[k]])) << k;
  const Vec3d spin{1, 2, 3};
  x.set(SphereField::Omega, slots.data() + 5, 1, &spin);
  std::vector<double> flat(3 * x.size(), -1);
  x.scatter(SphereField::Omega, slots.data(), flat.data());
  EXPECT_EQ(flat[16], 2.0);
  std::vector<std::int64_t> ids(x.size());
  x.copy_ids(ids.data());
  const ParticleSystem after = st->state();  // id order: id rank = index, ids 1..n
  EXPECT_EQ(after.omega[std::size_t(ids[5] - 1)].z, 3.0);
  EXPECT_DOUBLE_EQ(x.iw2_sum(), 0.0);  // smooth spheres' rotation is no energy of the engine's
  // A smooth scene without spins allocates none and gives zeros.
  auto plain = make_stepper(test::gas(100, 0.2, 1), {}, StepperConfig{});
  std::vector<Vec3d> zero(1, Vec3d{7, 7, 7});
  state_exchange(*plain).copy(SphereField::Omega, slots.data(), 1, zero.data());
  EXPECT_TRUE(same_bits(zero[0], Vec3d{}));
}

TEST(SmoothSpins, DataFilesAndDumpsCarryThem) {
  const ParticleSystem s = spinning(50, 0.2, {true, true, true}, false);
  auto st = make_stepper(s, {}, StepperConfig{});
  st->run(50);
  std::stringstream data;
  write_data(data, st->state(), "spins");
  expect_spins_kept(s, read_data(data, "spins", {true, true, true}), "data file");
  // A dump of smooth spheres with spins has the wx wy wz columns; without spins it has none.
  const std::string path = ::testing::TempDir() + "hs_smooth_spins.dump";
  {
    DumpWriter d(path);
    d.write_frame(0, st->state());
    d.commit();
  }
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("ITEM: ATOMS id type radius x y z vx vy vz ix iy iz wx wy wz\n"), std::string::npos);
  {
    DumpWriter d(path);
    d.write_frame(0, test::gas(20, 0.2, 1));
    d.commit();
  }
  std::ifstream in2(path);
  std::string plain((std::istreambuf_iterator<char>(in2)), std::istreambuf_iterator<char>());
  EXPECT_NE(plain.find("ITEM: ATOMS id type radius x y z vx vy vz ix iy iz\n"), std::string::npos);
  std::remove(path.c_str());
}
