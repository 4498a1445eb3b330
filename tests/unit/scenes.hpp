#pragma once
// Initial states shared by the engines' tests.
#include "hardsphere/init.hpp"

namespace hardsphere::test {

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
