#include "init/dense_packing.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/particles.hpp"

namespace hardsphere {

namespace {

// How far below anneal_start a failed first quench is retried, and how often.
constexpr double kRetryStep = 0.02;
constexpr int kRetries = 5;

double packing_fraction(const Box& box, std::int64_t n, double r) {
  return double(n) * 4.0 / 3.0 * M_PI * r * r * r / box.volume();
}

double radius_at(const Box& box, std::int64_t n, double phi) {
  return std::cbrt(phi * box.volume() * 3.0 / (4.0 * M_PI * double(n)));
}

// The event engine needs periodic axes of more than three diameters (cells plus a shell).
bool dynamics_fit(const Box& box, double r) {
  for (int d = 0; d < 3; ++d)
    if (box.periodic[d] && box.length(d) < 3.3 * 2 * r) return false;
  return true;
}

// Hard-sphere dynamics from Maxwell-Boltzmann velocities for a fixed number of events.
void relax(const Box& box, std::vector<Vec3d>& x, double r, double events_per_sphere, Rng& rng, std::int64_t& events) {
  ParticleSystem sys;
  sys.box = box;
  sys.reserve(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) sys.push_back(std::int64_t(i) + 1, 1, r, 1.0, x[i], {});
  assign_velocities(sys, 1.0, std::nullopt, rng);
  EventEngine engine(sys);
  engine.advance_events(std::int64_t(events_per_sphere * double(x.size())));
  events += engine.counters().events;
  x = engine.state().pos;
}

}  // namespace

std::vector<Vec3d> dense_packing(const Box& box, std::int64_t n, double radius, Rng& rng, const DensePackingConfig& cfg,
                                 DensePackingStats* stats) {
  DensePackingStats local;
  DensePackingStats& st = stats ? *stats : local;
  st = {};
  const double target = packing_fraction(box, n, radius);
  std::vector<Vec3d> x(std::size_t(std::max<std::int64_t>(n, 0)));
  for (auto& p : x)
    for (int d = 0; d < 3; ++d) {
      const double lo = box.periodic[d] ? box.lo[d] : box.lo[d] + radius;
      const double len = box.periodic[d] ? box.length(d) : std::max(0.0, box.length(d) - 2 * radius);
      p[d] = lo + rng.uniform() * len;
    }
  auto radius_for = [&](double phi) { return phi >= target ? radius : radius_at(box, n, phi); };
  auto fail = [&](const std::string& why) {
    return InputError("dense packing could not reach packing fraction " + format_number(target) + ": " + why +
                      " (the generator reaches " + format_number(kDenseLimit) +
                      " in a periodic box of a few thousand spheres, " + "less between walls)");
  };

  // First quench: straight to the target when it is low enough, else (or when that jams, as
  // walls can make it) to a looser packing, which is then compressed in stages.
  // (A box made from a packing fraction gives it back with round-off.)
  double phi = target <= cfg.direct_limit * (1 + 1e-12) ? target : std::min(target, cfg.anneal_start);
  for (int retry = 0;; ++retry) {
    if (separate_spheres(box, x, radius_for(phi), cfg.quench, &st.quench)) break;
    if (retry == kRetries) throw fail("even the first quench at " + format_number(phi) + " failed");
    phi = phi > cfg.anneal_start ? cfg.anneal_start : phi - kRetryStep;
  }
  st.densest = phi;

  double step = cfg.first_step;
  while (phi < target && step >= cfg.min_step && st.stages < cfg.max_stages) {
    if (!dynamics_fit(box, radius_for(phi))) break;
    ++st.stages;
    relax(box, x, radius_for(phi), cfg.events_per_sphere, rng, st.events);
    const double next = std::min(target, phi + step);
    std::vector<Vec3d> grown = x;
    QuenchConfig q = cfg.quench;
    q.max_iterations = cfg.stage_iterations;
    if (separate_spheres(box, grown, radius_for(next), q, &st.quench)) {
      x = std::move(grown);
      phi = next;
      st.densest = phi;
    } else {
      step *= 0.5;  // retry from the relaxed packing (relaxed once more) with a smaller step
    }
  }
  if (phi < target) throw fail("the densest packing reached was " + format_number(st.densest));

  // A quench ends at the edge of jamming, with a pressure far above the hard-sphere fluid's or
  // glass's at this density: let the packing relax, then separate the pairs the dynamics left in
  // contact (round-off can leave them a hair inside).
  if (cfg.final_events_per_sphere > 0 && dynamics_fit(box, radius)) {
    std::vector<Vec3d> relaxed = x;
    relax(box, relaxed, radius, cfg.final_events_per_sphere, rng, st.events);
    QuenchConfig q = cfg.quench;
    q.inflation = cfg.final_inflation;
    q.max_iterations = cfg.stage_iterations;
    if (separate_spheres(box, relaxed, radius, q, &st.quench)) x = std::move(relaxed);
  }
  return x;
}

}  // namespace hardsphere
