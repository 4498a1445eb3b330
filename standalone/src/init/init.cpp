#include "hardsphere/init.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/neighbour_entry.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/stepper.hpp"
#include "init/dense_packing.hpp"
#include "init/lattice_sites.hpp"
#include "scene/cell_grid.hpp"

namespace hardsphere {

InitMethod parse_init_method(const std::string& s) {
  if (s == "auto") return InitMethod::Auto;
  if (s == "random") return InitMethod::Random;
  if (s == "lattice") return InitMethod::Lattice;
  if (s == "dense") return InitMethod::Dense;
  throw InputError("unknown init method '" + s + "' (expected auto, random, lattice or dense)");
}

namespace {

// Lowest and highest allowed centre coordinate along axis d for a sphere of radius r.
double lower(const Box& b, int d, double r) { return b.periodic[d] ? b.lo[d] : b.lo[d] + r; }
double span(const Box& b, int d, double r) { return b.periodic[d] ? b.length(d) : b.length(d) - 2 * r; }

// A box made from a packing fraction (as the CLI's --phi does) gives it back with round-off.
bool above(double phi, double limit) { return phi > limit * (1 + 1e-12); }

void zero_momentum(ParticleSystem& sys) {
  Vec3d p{};
  double mtot = 0;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    p += sys.mass[i] * sys.vel[i];
    mtot += sys.mass[i];
  }
  const Vec3d vcm = (1.0 / mtot) * p;
  for (auto& v : sys.vel) v -= vcm;
}

void rescale_to(ParticleSystem& sys, double t) {
  const double now = temperature(sys);
  if (now > 0) {
    const double f = std::sqrt(t / now);
    for (auto& v : sys.vel) v = f * v;
  }
}

Vec3d random_direction(Rng& rng) {
  // Uniform on the sphere: z uniform in [-1, 1], azimuth uniform.
  const double z = 2 * rng.uniform() - 1, phi = 2 * M_PI * rng.uniform();
  const double s = std::sqrt(std::max(0.0, 1 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

// Largest overlap with another sphere or with a wall (growth can leave either behind).
double max_violation(const ParticleSystem& sys) {
  double worst = max_overlap(sys);
  for (std::size_t i = 0; i < sys.size(); ++i)
    for (int d = 0; d < 3; ++d) {
      if (sys.box.periodic[d]) continue;
      worst = std::max(worst, sys.box.lo[d] + sys.radius[i] - sys.pos[i][d]);
      worst = std::max(worst, sys.pos[i][d] + sys.radius[i] - sys.box.hi[d]);
    }
  return worst;
}

// Contact events the lattice route may spend per sphere: normal runs take 20-650 (phi 0.3-0.63),
// but near the route's jamming point, which walls lower, the events per step grow without bound.
constexpr std::int64_t kLatticeEventsPerSphere = 5000;

// Runs the stepper, charging its contact events to `budget`; false once the budget is spent.
bool run_dynamics(ParticleSystem& sys, double dt, std::int64_t steps, std::int64_t& budget) {
  StepperConfig cfg;
  cfg.dt = dt;
  cfg.max_events_per_step = std::max<std::int64_t>(1, budget / steps);
  auto engine = make_stepper(sys, Physics{}, cfg);
  engine->run(steps);
  budget -= engine->counters().collisions + engine->counters().wall_collisions;
  sys = engine->state();
  return budget > 0 && engine->counters().unresolved_steps == 0;
}

void lattice_route(ParticleSystem& sys, const InitSpec& spec, Rng& rng) {
  const double target_r = spec.radius;
  auto lattice = lattice_sites(spec.box, spec.n, target_r);
  auto& sites = lattice.pos;
  // Start dilute enough to melt quickly: packing fraction at most 0.3, and fitting the lattice.
  const double phi = double(spec.n) * 4.0 / 3.0 * M_PI * std::pow(target_r, 3) / spec.box.volume();
  double r0 = target_r * std::min(1.0, std::cbrt(0.30 / phi));
  r0 = std::min(r0, 0.49 * lattice.spacing);
  // Sites this close only come from a box too narrow for n spheres of this size; growing from
  // them would take unboundedly many steps.
  if (!(r0 >= 1e-3 * target_r))
    throw InputError("the box is too narrow for " + std::to_string(spec.n) + " spheres of radius " +
                     format_number(target_r) + " on a lattice (sites " + format_number(lattice.spacing) + " apart)");
  // Choose which sites to fill (a partial Fisher-Yates shuffle) so vacancies are random.
  for (std::int64_t i = 0; i < spec.n; ++i)
    std::swap(sites[std::size_t(i)], sites[std::size_t(i + std::int64_t(rng.below(sites.size() - std::size_t(i))))]);
  sys.reserve(std::size_t(spec.n));
  for (std::int64_t i = 0; i < spec.n; ++i) sys.push_back(i + 1, 1, r0, spec.mass, sites[std::size_t(i)], {});
  assign_velocities(sys, spec.temperature, std::nullopt, rng);

  const double v_rms = std::sqrt(3 * spec.temperature / spec.mass);
  const double dt = 0.02 * 2 * target_r / v_rms;
  std::int64_t budget = kLatticeEventsPerSphere * spec.n;
  auto jammed = [&] {
    return InputError("lattice route could not reach packing fraction " + format_number(phi) +
                      ": the spheres jammed near " + format_number(sys.packing_fraction()) + " (" +
                      std::to_string(kLatticeEventsPerSphere) + " collisions per sphere spent; walls lower the reach)");
  };
  // Melt: about 40 collisions per sphere at the starting density.
  if (!run_dynamics(sys, dt, 300, budget)) throw jammed();
  // Compress by growing every sphere a little at a time; the collision rule pushes apart the
  // approaching pairs that growth makes overlap, and receding ones separate by themselves.
  const double growth = 0.002;
  const auto stages = std::int64_t(std::ceil(std::log(target_r / r0) / std::log1p(growth)));
  for (std::int64_t k = 1; k <= stages; ++k) {
    const double r = std::min(target_r, r0 * std::pow(1 + growth, double(k)));
    for (auto& x : sys.radius) x = k == stages ? target_r : r;
    if (!run_dynamics(sys, dt, 4, budget)) throw jammed();
  }
  for (int attempt = 0; attempt < 200 && max_violation(sys) > 0; ++attempt)
    if (!run_dynamics(sys, dt, 5, budget)) throw jammed();
  const double left = max_violation(sys);
  if (left > 0) {
    throw InputError("lattice route could not reach packing fraction " + format_number(phi) + ": overlap " +
                     format_number(left) + " remains after compression (too dense for a fluid; the route is for <= " +
                     format_number(kLatticeRouteLimit) + ")");
  }
  // Forget the compression: equilibrate briefly at the final density.
  if (!run_dynamics(sys, dt, 100, budget)) throw jammed();
}

void dense_route(ParticleSystem& sys, const InitSpec& spec, Rng& rng) {
  const auto pos = dense_packing(spec.box, spec.n, spec.radius, rng);
  sys.reserve(std::size_t(spec.n));
  for (std::int64_t i = 0; i < spec.n; ++i) sys.push_back(i + 1, 1, spec.radius, spec.mass, pos[std::size_t(i)], {});
}

}  // namespace

void place_random(ParticleSystem& sys, std::int64_t n, double radius, double mass, Rng& rng,
                  std::int64_t max_attempts_per_sphere, const std::vector<WallShape>& walls) {
  const Box& box = sys.box;
  const double diameter = 2 * radius;
  const CellGrid grid = CellGrid::with_min_width(box, diameter, 2 * n + 27);
  std::vector<std::vector<std::uint32_t>> members(std::size_t(grid.size()));
  sys.reserve(std::size_t(n));
  for (std::int64_t placed = 0; placed < n; ++placed) {
    bool ok = false;
    for (std::int64_t attempt = 0; attempt < max_attempts_per_sphere && !ok; ++attempt) {
      Vec3d p;
      for (int d = 0; d < 3; ++d) p[d] = lower(box, d, radius) + rng.uniform() * span(box, d, radius);
      ok = true;
      // A funnel's spheres start inside it (its outside is not a wall).
      for (const WallShape& w : walls) {
        const double gap = shape_gap_at(w, w.start_time(), p, radius);
        ok = ok && gap >= 0 && (w.kind != ShapeKind::Cone || std::isfinite(gap));
      }
      if (!ok) continue;
      const int cell = grid.cell_of(p.x, p.y, p.z);
      grid.for_each_neighbour(cell, [&](int nb) {
        if (!ok) return;
        for (std::uint32_t j : members[std::size_t(nb)]) {
          Vec3d dr = p - sys.pos[j];
          for (int d = 0; d < 3; ++d)
            if (box.periodic[d]) dr[d] -= box.length(d) * std::nearbyint(dr[d] / box.length(d));
          if (dot(dr, dr) < diameter * diameter) {
            ok = false;
            return;
          }
        }
      });
      if (ok) {
        members[std::size_t(cell)].push_back(std::uint32_t(sys.size()));
        sys.push_back(placed + 1, 1, radius, mass, p, {});
      }
    }
    if (!ok) {
      const double phi = double(n) * 4.0 / 3.0 * M_PI * radius * radius * radius / box.volume();
      throw InputError("random insertion placed only " + std::to_string(placed) + " of " + std::to_string(n) +
                       " spheres (packing fraction " + format_number(phi) +
                       " is too dense for it; use --init lattice, which reaches " + format_number(kLatticeRouteLimit) +
                       ", or --init dense, which reaches " + format_number(kDenseLimit) + ")");
    }
  }
}

void assign_velocities(ParticleSystem& sys, double t, std::optional<double> speed, Rng& rng) {
  const std::size_t n = sys.size();
  if (speed) {
    const bool equal_mass =
        sys.monodisperse() || std::all_of(sys.mass.begin(), sys.mass.end(), [&](double m) { return m == sys.mass[0]; });
    if (equal_mass && n >= 2) {
      // Pairs with opposite velocities (a triple at 120 degrees if n is odd): every sphere has
      // exactly the given speed and the total momentum is exactly zero.
      std::size_t i = 0;
      if (n % 2 == 1 && n >= 3) {
        const Vec3d a = random_direction(rng);
        Vec3d b = random_direction(rng);
        b -= dot(a, b) * a;
        b = (1.0 / norm(b)) * b;
        const double c = -0.5, s = std::sqrt(3.0) / 2;
        sys.vel[0] = *speed * a;
        sys.vel[1] = *speed * (c * a + s * b);
        sys.vel[2] = *speed * (c * a - s * b);
        i = 3;
      }
      for (; i + 1 < n; i += 2) {
        const Vec3d d = random_direction(rng);
        sys.vel[i] = *speed * d;
        sys.vel[i + 1] = -(*speed * d);
      }
      return;
    }
    for (std::size_t i = 0; i < n; ++i) sys.vel[i] = *speed * random_direction(rng);
    if (n > 1) zero_momentum(sys);
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double s = std::sqrt(t / sys.mass[i]);
    sys.vel[i] = {s * rng.normal(), s * rng.normal(), s * rng.normal()};
  }
  if (n > 1) zero_momentum(sys);
  rescale_to(sys, t);
}

void assign_angular_velocities(ParticleSystem& sys, double t, double q, Rng& rng) {
  sys.omega.resize(sys.size());
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const double s = std::sqrt(t / (q * sys.mass[i] * sys.radius[i] * sys.radius[i]));
    sys.omega[i] = {s * rng.normal(), s * rng.normal(), s * rng.normal()};
  }
}

namespace {

//! The spec's numbers and the box, refused with the value at fault before anything is made.
void check_init_spec(const InitSpec& spec) {
  validate_box(spec.box, "initial state");
  if (spec.n < 1) throw InputError("number of particles n = " + std::to_string(spec.n) + " must be >= 1");
  if (spec.n > std::int64_t(kMaxAdjIndex) + 1)
    throw InputError("number of particles n = " + std::to_string(spec.n) + " is more than the engines hold (" +
                     std::to_string(std::int64_t(kMaxAdjIndex) + 1) + ")");
  if (!(std::isfinite(spec.radius) && spec.radius > 0))
    throw InputError("radius " + format_number(spec.radius) + " must be positive and finite");
  if (!(std::isfinite(spec.mass) && spec.mass > 0))
    throw InputError("mass " + format_number(spec.mass) + " must be positive and finite");
  if (!(std::isfinite(spec.temperature) && spec.temperature > 0))
    throw InputError("temperature " + format_number(spec.temperature) + " must be positive and finite");
  if (spec.rotational_temperature &&
      !(std::isfinite(*spec.rotational_temperature) && *spec.rotational_temperature >= 0))
    throw InputError("rotational temperature " + format_number(*spec.rotational_temperature) +
                     " must be finite and >= 0");
  if (spec.rotational_temperature && !(spec.inertia > 0 && spec.inertia <= 2.0 / 3.0))
    throw InputError("inertia " + format_number(spec.inertia) + " must be in (0, 2/3]");
  if (spec.speed && !(std::isfinite(*spec.speed) && *spec.speed > 0))
    throw InputError("init speed " + format_number(*spec.speed) + " must be positive and finite");
  // The kinetic energy, sum m v^2 = 3 N T, must stay finite (rescaling to T divides by it).
  const double mv2 =
      spec.speed ? double(spec.n) * spec.mass * *spec.speed * *spec.speed : 3.0 * double(spec.n) * spec.temperature;
  if (!(mv2 <= 1e300))
    throw InputError(
        (spec.speed ? "init speed " + format_number(*spec.speed) : "temperature " + format_number(spec.temperature)) +
        " with " + std::to_string(spec.n) + " spheres of mass " + format_number(spec.mass) +
        " gives a kinetic energy (sum m v^2 = " + format_number(mv2) + ") that overflows double precision");
  for (int d = 0; d < 3; ++d) {
    if (spec.box.periodic[d] && spec.box.length(d) < 4 * spec.radius)
      throw InputError("periodic box length " + format_number(spec.box.length(d)) + " is less than two diameters (" +
                       format_number(4 * spec.radius) + ")");
    // A sphere pinched between two walls would bounce between them infinitely often.
    if (!spec.box.periodic[d] && spec.box.length(d) <= 2 * spec.radius)
      throw InputError("box length " + format_number(spec.box.length(d)) +
                       " between walls is not more than one diameter (" + format_number(2 * spec.radius) + ")");
  }
}

//! The route to the spec's packing fraction (auto's choice), refused where none reaches it.
InitMethod init_method(const InitSpec& spec) {
  const double phi = double(spec.n) * 4.0 / 3.0 * M_PI * std::pow(spec.radius, 3) / spec.box.volume();
  if (above(phi, kClosePacking))
    throw InputError("packing fraction " + format_number(phi) + " is impossible: above close packing " +
                     format_number(kClosePacking));
  if (spec.method == InitMethod::Auto && above(phi, kDenseLimit))
    throw InputError("packing fraction " + format_number(phi) + " is above " + format_number(kDenseLimit) +
                     ", the densest state the initialiser promises (random close packing is near 0.64, close packing " +
                     format_number(kClosePacking) + "); --init dense tries denser ones");
  InitMethod method = spec.method;
  if (!spec.walls.empty()) {
    if (method != InitMethod::Auto && method != InitMethod::Random)
      throw InputError(std::string("the ") + (method == InitMethod::Lattice ? "lattice" : "dense") +
                       " initial state does not know shaped walls (" + spec.walls.front().source +
                       "): random insertion places spheres clear of them (init random)");
    return InitMethod::Random;
  }
  if (method == InitMethod::Auto) {
    method = phi <= kRandomInsertionLimit      ? InitMethod::Random
             : !above(phi, kLatticeRouteLimit) ? InitMethod::Lattice
                                               : InitMethod::Dense;
  }
  if (method == InitMethod::Lattice && above(phi, kLatticeRouteLimit))
    throw InputError("packing fraction " + format_number(phi) + " is above " + format_number(kLatticeRouteLimit) +
                     ", the densest fluid the lattice route makes (freezing is at 0.494); --init dense reaches " +
                     format_number(kDenseLimit));
  return method;
}

}  // namespace

ParticleSystem make_initial_state(const InitSpec& spec) {
  check_init_spec(spec);
  const InitMethod method = init_method(spec);
  Rng rng(spec.seed);
  ParticleSystem sys;
  sys.box = spec.box;
  if (method == InitMethod::Random) {
    place_random(sys, spec.n, spec.radius, spec.mass, rng, 2000, spec.walls);
  } else if (method == InitMethod::Lattice && spec.method == InitMethod::Auto) {
    // Walls can jam the lattice route below its limit (small boxes): the dense generator
    // separates spheres without dynamics, so it is the fallback.
    try {
      lattice_route(sys, spec, rng);
    } catch (const InputError&) {
      sys = ParticleSystem{};
      sys.box = spec.box;
      dense_route(sys, spec, rng);
    }
  } else if (method == InitMethod::Lattice) {
    lattice_route(sys, spec, rng);
  } else {
    dense_route(sys, spec, rng);
  }
  assign_velocities(sys, spec.temperature, spec.speed, rng);
  // After the velocities, so a rough scene starts from the smooth one's positions and velocities.
  if (spec.rotational_temperature) assign_angular_velocities(sys, *spec.rotational_temperature, spec.inertia, rng);
  validate_and_wrap(sys, "initial state");
  return sys;
}

}  // namespace hardsphere
