#include "hardsphere/physics.hpp"

#include <algorithm>
#include <cmath>

#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"

namespace hardsphere {

std::array<double, 3> without_rounding(std::array<double, 3> g) {
  const double largest = std::max({std::abs(g[0]), std::abs(g[1]), std::abs(g[2])});
  for (double& c : g)
    if (std::abs(c) <= kGravityRounding * largest) c = 0;
  return g;
}

Physics validated(Physics p, const std::array<bool, 3>& periodic, const PhysicsNames& names) {
  const std::string e = format_number(p.restitution), tc = format_number(p.contact_time);
  if (!(p.restitution > 0 && p.restitution <= 1))
    throw InputError(names.restitution + " " + e + " must be in (0, 1] (1: elastic)");
  if (!(p.contact_time >= 0 && std::isfinite(p.contact_time)))
    throw InputError(names.contact_time + " " + tc + " must be finite and >= 0");
  if (p.restitution < 1 && p.contact_time == 0)
    throw InputError(names.contact_time + " 0 with " + names.restitution + " " + e +
                     ": an inelastic collapse (infinitely many collisions in finite time) would never end; give " +
                     names.contact_time + " a value > 0");
  if (!(p.resting_time >= 0 && std::isfinite(p.resting_time)))
    throw InputError(names.resting_time + " " + format_number(p.resting_time) + " must be finite and >= 0");
  const std::string beta = format_number(p.tangential_restitution);
  if (!(p.tangential_restitution >= -1 && p.tangential_restitution <= 1))
    throw InputError(names.tangential_restitution + " " + beta +
                     " must be in [-1, 1] (-1: smooth, 1: perfectly rough)");
  if (!(p.friction >= 0))
    throw InputError(names.friction + " " + format_number(p.friction) + " must be >= 0 (infinite: no sliding)");
  if (std::isfinite(p.friction) && !p.rough())
    throw InputError(names.friction + " " + format_number(p.friction) + " needs a " + names.tangential_restitution +
                     " above -1 as its sticking limit beta0");
  if (!(p.inertia > 0 && p.inertia <= 2.0 / 3.0))
    throw InputError(names.inertia + " " + format_number(p.inertia) +
                     " must be in (0, 2/3] (I = q m r^2; 0.4: solid sphere, 2/3: thin shell)");
  for (int d = 0; d < 3; ++d) {
    const double g = p.gravity[std::size_t(d)];
    if (!std::isfinite(g))
      throw InputError(names.gravity + " component " + "xyz"[d] + " = " + format_number(g) + " must be finite");
  }
  p.gravity = without_rounding(p.gravity);
  for (int d = 0; d < 3; ++d) {
    const double g = p.gravity[std::size_t(d)];
    if (g != 0 && periodic[std::size_t(d)])
      throw InputError(names.gravity + " along periodic axis " + "xyz"[d] + " (" + format_number(g) +
                       ") would accelerate the spheres without end; put " + names.walls);
  }
  return p;
}

}  // namespace hardsphere
