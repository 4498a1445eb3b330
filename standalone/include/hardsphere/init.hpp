#pragma once
//! Initial states: positions (random insertion, or lattice + melt + compression for dense
//! states) and velocities (Maxwell-Boltzmann or one speed), deterministic per seed.
#include <cstdint>
#include <optional>
#include <string>

#include "hardsphere/particles.hpp"
#include "hardsphere/rng.hpp"

namespace hardsphere {

enum class InitMethod { Auto, Random, Lattice };
InitMethod parse_init_method(const std::string& s);

struct InitSpec {
  std::int64_t n = 1000;
  Box box;
  double radius = 0.5;
  double mass = 1.0;
  double temperature = 1.0;
  std::optional<double> speed;  //!< all particles with this speed instead of Maxwell-Boltzmann
  std::uint64_t seed = 1;
  InitMethod method = InitMethod::Auto;
};

//! Above this packing fraction Auto uses the lattice route: random insertion slows down
//! sharply towards its jamming limit near 0.38 and already fails now and then at 0.30 for a
//! few hundred spheres (2000 attempts per sphere).
constexpr double kRandomInsertionLimit = 0.25;
//! The densest state the lattice route promises (freezing is at 0.494; 0.55 still melts).
constexpr double kLatticeRouteLimit = 0.55;

//! A complete, validated initial state. Throws InputError for impossible requests.
ParticleSystem make_initial_state(const InitSpec& spec);

//! Seed-paper insertion: uniform random positions, rejected on overlap (cell grid). Throws
//! InputError naming how many spheres fitted if the packing cannot be reached.
void place_random(ParticleSystem& sys, std::int64_t n, double radius, double mass, Rng& rng,
                  std::int64_t max_attempts_per_sphere = 2000);

//! Maxwell-Boltzmann velocities at temperature T (or one speed, isotropic), total momentum
//! zeroed and T = sum m v^2 / 3N set exactly.
void assign_velocities(ParticleSystem& sys, double temperature, std::optional<double> speed, Rng& rng);


}  // namespace hardsphere
