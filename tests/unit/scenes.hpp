#pragma once
// Initial states shared by the engines' tests.
#include <cmath>
#include <optional>

#include "hardsphere/init.hpp"

namespace hardsphere::test {

//! n unit spheres at packing fraction phi in a cubic box (Maxwell-Boltzmann at T = 1, or all
//! with one speed), generated deterministically from `seed`.
inline ParticleSystem gas(std::int64_t n, double phi, std::uint64_t seed, std::optional<double> speed = std::nullopt,
                          std::array<bool, 3> periodic = {true, true, true}, InitMethod method = InitMethod::Auto) {
  InitSpec spec;
  spec.n = n;
  const double l = std::cbrt(double(n) * M_PI / 6.0 / phi);
  spec.box = Box::from_lengths({l, l, l}, periodic);
  spec.seed = seed;
  spec.speed = speed;
  spec.method = method;
  return make_initial_state(spec);
}

//! Two spheres (ids 1 and 2) in a cubic box of the given length, for analytic cases.
inline ParticleSystem two(Vec3d r1, Vec3d v1, Vec3d r2, Vec3d v2, double rad1 = 0.5, double rad2 = 0.5, double m1 = 1,
                          double m2 = 1, double length = 10, std::array<bool, 3> periodic = {true, true, true}) {
  ParticleSystem s;
  s.box = Box::from_lengths({length, length, length}, periodic);
  s.push_back(1, 1, rad1, m1, r1, v1);
  s.push_back(2, 1, rad2, m2, r2, v2);
  return s;
}

//! n spheres in a 9^3 box, periodic in x and y, walls in z; every third sphere is smaller
//! (radius 0.3) and lighter (mass 0.25): a polydisperse scene that needs every general path.
inline ParticleSystem binary_mixture_with_walls(std::int64_t n) {
  InitSpec spec;
  spec.n = n;
  spec.box = Box::from_lengths({9, 9, 9}, {true, true, false});
  spec.seed = 3;
  auto s = make_initial_state(spec);
  for (std::size_t i = 0; i < s.size(); i += 3) {
    s.radius[i] = 0.3;
    s.mass[i] = 0.25;
  }
  return s;
}

}  // namespace hardsphere::test
