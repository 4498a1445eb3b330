// Image flags: every engine counts the box lengths it takes off a periodic coordinate, so
// position + image * L is continuous in time (mean-squared displacements from dumps), and data
// files carry them through.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/stepper.hpp"
#include "scenes.hpp"

using namespace hardsphere;

namespace {

Vec3d unwrapped(const ParticleSystem& s, std::size_t i) {
  Vec3d u = s.pos[i];
  for (int d = 0; d < 3; ++d)
    if (s.box.periodic[d]) u[d] += double(s.image[i][std::size_t(d)]) * s.box.length(d);
  return u;
}

// Collisions exchange equal and opposite impulses at one point, so with periodic boundaries the
// mass-weighted sum of unwrapped positions moves exactly with the total momentum: a missed or
// double-counted wrap would shift it by a box length over N.
Vec3d centre_of_mass(const ParticleSystem& s) {
  Vec3d c{0, 0, 0};
  double m = 0;
  for (std::size_t i = 0; i < s.size(); ++i) c = c + s.mass[i] * unwrapped(s, i), m += s.mass[i];
  return (1.0 / m) * c;
}

template <class Advance>
void expect_centre_fixed(const ParticleSystem& start, Advance advance) {
  const Vec3d c0 = centre_of_mass(start);
  long wraps = 0;
  for (int block = 0; block < 5; ++block) {
    const ParticleSystem s = advance();
    const Vec3d c = centre_of_mass(s);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(c[d], c0[d], 1e-9 * s.box.length(d)) << "block " << block << " axis " << d;
    for (const auto& img : s.image) wraps += std::abs(img[0]) + std::abs(img[1]) + std::abs(img[2]);
  }
  EXPECT_GT(wraps, 1000);  // the spheres did cross the periodic faces, many times
}

}  // namespace

TEST(ImageFlags, StepperKeepsUnwrappedPositionsContinuous) {
  const ParticleSystem s = test::gas(500, 0.3, 7);  // total momentum zero
  StepperConfig cfg;
  cfg.dt = 0.01;
  auto st = make_stepper(s, {}, cfg);
  expect_centre_fixed(s, [&] {
    st->run(400);
    return st->state();
  });
}

TEST(ImageFlags, EventEngineKeepsUnwrappedPositionsContinuous) {
  const ParticleSystem s = test::gas(500, 0.3, 7);
  EventEngine e(s);
  expect_centre_fixed(s, [&] {
    e.advance(4.0);
    return e.state();
  });
}

TEST(ImageFlags, StartFromTheFileAndTravelThroughDataFiles) {
  // One sphere flying along x through a periodic box of 10 from image -3: after 37 time units
  // it has crossed 3 or 4 more faces; the unwrapped position is exact and survives a data file.
  ParticleSystem s = test::two({1.0, 5.0, 5.0}, {1.0, 0.0, 0.0}, {5.0, 1.0, 1.0}, {0.0, 0.0, 0.0});
  s.image[0] = {-3, 2, 0};
  const double x0 = unwrapped(s, 0).x;
  StepperConfig cfg;
  cfg.dt = 0.1;
  auto st = make_stepper(s, {}, cfg);
  st->run(370);
  EventEngine e(s);
  e.advance(37.0);
  for (const ParticleSystem& out : {st->state(), e.state()}) {
    EXPECT_NEAR(unwrapped(out, 0).x, x0 + 37.0, 1e-9);
    EXPECT_EQ(out.image[0][1], 2);
    std::stringstream file;
    write_data(file, out, "images");
    const ParticleSystem back = read_data(file, "images.data", {true, true, true});
    EXPECT_EQ(back.image[0], out.image[0]);
    EXPECT_EQ(back.image[1], out.image[1]);
  }
}

TEST(ImageFlags, WallAxesHaveNone) {
  std::stringstream file(
      "walls\n\n1 atoms\n1 atom types\n0 10 xlo xhi\n0 10 ylo yhi\n0 10 zlo zhi\n\nAtoms # sphere\n\n"
      "1 1 1.0 1.9098593171027443 5 5 5 4 -2 7\n");
  const ParticleSystem s = read_data(file, "walls.data", {true, true, false});
  EXPECT_EQ(s.image[0][0], 4);
  EXPECT_EQ(s.image[0][1], -2);
  EXPECT_EQ(s.image[0][2], 0);
}
