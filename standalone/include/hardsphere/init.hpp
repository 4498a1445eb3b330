#pragma once
//! Initial states: positions (random insertion; lattice + melt + compression for dense fluids;
//! a soft-sphere quench for amorphous states beyond) and velocities (Maxwell-Boltzmann or one
//! speed), deterministic per seed. See docs/initial_states.md.
#include <cstdint>
#include <optional>
#include <string>

#include "hardsphere/particles.hpp"
#include "hardsphere/rng.hpp"
#include "hardsphere/wall_shapes.hpp"

namespace hardsphere {

enum class InitMethod { Auto, Random, Lattice, Dense };
InitMethod parse_init_method(const std::string& s);

struct InitSpec {
  std::int64_t n = 1000;
  Box box;
  double radius = 0.5;
  double mass = 1.0;
  double temperature = 1.0;
  std::optional<double> speed;  //!< all particles with this speed instead of Maxwell-Boltzmann
  //! Rough spheres: angular velocities drawn at this temperature (none: all zero), with I = q m r^2.
  std::optional<double> rotational_temperature;
  double inertia = 0.4;  //!< q of I = q m r^2
  std::uint64_t seed = 1;
  InitMethod method = InitMethod::Auto;
  //! Shaped walls (Physics::shapes): random insertion places spheres clear of them (the only
  //! method that takes them; Auto chooses it).
  std::vector<WallShape> walls;
};

//! Above this packing fraction Auto uses the lattice route: random insertion slows down
//! sharply towards its jamming limit near 0.38 and already fails now and then at 0.30 for a
//! few hundred spheres (2000 attempts per sphere).
constexpr double kRandomInsertionLimit = 0.25;
//! The densest state the lattice route promises (freezing is at 0.494; 0.55 still melts).
//! Auto uses the dense quench above it.
constexpr double kLatticeRouteLimit = 0.55;
//! The densest state the dense generator promises in a periodic box (random close packing is
//! near 0.64): Auto refuses denser ones, --init dense tries them. Walls lower the reach; the
//! generator then refuses after a bounded number of stages, naming the densest it reached.
constexpr double kDenseLimit = 0.64;
//! Close packing, pi / sqrt(18): no state of equal spheres is denser.
constexpr double kClosePacking = 0.74048048969306104;

//! A complete, validated initial state. Throws InputError for impossible requests.
ParticleSystem make_initial_state(const InitSpec& spec);

//! Seed-paper insertion: uniform random positions, rejected on overlap (cell grid). Throws
//! InputError naming how many spheres fitted if the packing cannot be reached.
void place_random(ParticleSystem& sys, std::int64_t n, double radius, double mass, Rng& rng,
                  std::int64_t max_attempts_per_sphere = 2000, const std::vector<WallShape>& walls = {});

//! Maxwell-Boltzmann angular velocities at temperature T: each component normal with variance
//! T / I, I = q m r^2 (total angular momentum not removed, T not rescaled).
void assign_angular_velocities(ParticleSystem& sys, double temperature, double inertia, Rng& rng);

//! Maxwell-Boltzmann velocities at temperature T (or one speed, isotropic), total momentum
//! zeroed and T = sum m v^2 / 3N set exactly.
void assign_velocities(ParticleSystem& sys, double temperature, std::optional<double> speed, Rng& rng);

}  // namespace hardsphere
