// One complete run of the event-driven engine as the CLI performs it (run_simulation with
// engine = event): initial state, equilibration in simulated time, a measured run split into
// blocks (for the error bar of Z and the collision rate), summary with the stepper's JSON keys
// where they mean the same thing.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/run_summary.hpp"
#include "hardsphere/scene_limits.hpp"
#include "hardsphere/simulation.hpp"
#include "io/tracker.hpp"

namespace hardsphere {

namespace {

//! Mean and standard error of the mean of block values.
std::pair<double, double> mean_error(const std::vector<double>& x) {
  const double n = double(x.size());
  if (x.empty()) return {0, 0};
  double m = 0;
  for (double v : x) m += v;
  m /= n;
  if (x.size() < 2) return {m, 0};
  double s = 0;
  for (double v : x) s += (v - m) * (v - m);
  return {m, std::sqrt(s / (n - 1) / n)};
}

//! A sphere re-lists its neighbours each time it has moved half the shell: at least
//! sum |v_i| t / (shell / 2) events, whatever collisions add. Refuse up front what the engine's
//! event limit would stop later.
void refuse_too_many_events(const ParticleSystem& sys, double shell, double time, double limit,
                            const std::array<double, 3>& gravity) {
  double speeds = 0;
  for (const Vec3d& v : sys.vel) speeds += norm(v);
  double bounces = wall_bounce_rate(sys) * time;
  // Under gravity a sphere falls across its gap G (at most the box) and bounces at least every
  // 2 sqrt(2 G / g), reaching speeds up to sqrt(2 g G): more bounces and list events.
  for (int d = 0; d < 3; ++d) {
    const double g = std::abs(gravity[std::size_t(d)]);
    if (g == 0) continue;
    const double gap = std::max(sys.box.length(d) - 2 * sys.max_radius(), 1e-300);
    bounces += double(sys.size()) * time * std::sqrt(g / (8 * gap));
    speeds += double(sys.size()) * std::sqrt(2 * g * gap);
  }
  const double events = speeds * time / (0.5 * shell) + bounces;
  if (events > limit) {
    std::ostringstream m;
    m << "the run would take at least " << events << " events (" << sys.size() << " spheres moving " << speeds * time
      << " in all over time " << time << ", a neighbour-list event every " << 0.5 * shell;
    if (bounces > 0) m << ", and " << bounces << " wall bounces";
    m << "), more than the limit of " << limit << "; shorten --time, lower the speeds or the gravity";
    throw InputError(m.str());
  }
}

}  // namespace

nlohmann::json run_event_simulation(const RunSpec& spec) {
  check_outputs(spec);
  if (!(spec.time > 0) || !std::isfinite(spec.time))
    throw InputError("time = " + std::to_string(spec.time) +
                     " must be positive and finite (event engine runs for a simulated time)");
  if (!(spec.equilibrate_time >= 0) || !std::isfinite(spec.equilibrate_time))
    throw InputError("equilibrate time = " + std::to_string(spec.equilibrate_time) + " must be >= 0");
  if (spec.blocks < 1) throw InputError("blocks = " + std::to_string(spec.blocks) + " must be >= 1");
  if (spec.histogram_bins < 1)
    throw InputError("--histogram-bins " + std::to_string(spec.histogram_bins) + " must be >= 1");

  ParticleSystem sys = initial_state(spec);
  EventConfig cfg = spec.event;
  cfg.max_events = spec.work_limit;
  EventEngine engine(sys, cfg);
  refuse_too_many_events(sys, engine.shell(), spec.time + spec.equilibrate_time, spec.work_limit, spec.event.gravity);
  std::optional<Tracker> tracker;  // the engine's state() is in input order, like sys
  if (spec.track_id) tracker.emplace(*spec.track_file, sys, *spec.track_id, spec.track_every, spec.time, "event");
  std::optional<DumpWriter> dump;
  if (spec.dump) dump.emplace(*spec.dump);
  std::optional<AtomicFile> json_file;
  if (spec.json && *spec.json != "-") json_file.emplace(*spec.json);

  if (spec.equilibrate_time > 0) {
    engine.advance(spec.equilibrate_time);
    sys = engine.state();
  }
  engine.reset_counters();
  const double e0 = kinetic_energy(sys);
  const double u0 = potential_energy(sys, spec.event.gravity);
  const Vec3d p0 = total_momentum(sys);
  const std::size_t n = sys.size();
  const double t0_temp = n ? 2 * e0 / (3.0 * double(n)) : 0.0;

  // Measured run in blocks; a dump frame (if asked for) after each block.
  double cpu = 0;
  std::vector<double> z_block, rate_block;
  if (dump) dump->write_frame(0, sys);
  // Runs `duration` further, stopping at each tracker sample time on the way (the engine's
  // state is exact at any time, so samples change nothing). A sample due within rounding of
  // the end is taken there.
  const double t_measure = engine.time();
  const auto advance = [&](double duration) {
    const double end = engine.time() + duration;
    if (tracker) {
      for (double t = tracker->next_time(); t_measure + t <= end + 1e-9 * tracker->every(); t = tracker->next_time()) {
        engine.advance(std::max(0.0, std::min(t_measure + t, end) - engine.time()));
        tracker->write(t, engine.sphere(tracker->index()));
      }
    }
    engine.advance(std::max(0.0, end - engine.time()));
  };
  const double block = spec.time / spec.blocks;
  double w_prev = 0;
  std::int64_t coll_prev = 0;
  for (int b = 0; b < spec.blocks; ++b) {
    const double t_start = engine.time();
    const double target = b + 1 == spec.blocks ? spec.time - engine.counters().sim_time : block;
    const double c0 = process_cpu_seconds();
    advance(target);
    cpu += process_cpu_seconds() - c0;
    const EventCounters& c = engine.counters();
    const double dt = engine.time() - t_start;
    z_block.push_back(compressibility_factor(c.pair_virial - w_prev, dt, n, t0_temp));
    rate_block.push_back(dt > 0 && n ? 2.0 * double(c.collisions - coll_prev) / (double(n) * dt) : 0.0);
    w_prev = c.pair_virial;
    coll_prev = c.collisions;
    if (dump) dump->write_frame(c.events, engine.state());
    if (spec.progress) spec.progress(double(b + 1) / spec.blocks, c.sim_time);
  }
  const ParticleSystem fin = engine.state();
  const EventCounters& c = engine.counters();

  const auto [z_mean, z_err] = mean_error(z_block);
  const auto [rate_mean, rate_err] = mean_error(rate_block);
  (void)z_mean;
  (void)rate_mean;

  RunTotals totals{e0, p0, c.sim_time, c.collisions, c.wall_collisions, c.pair_virial, c.wall_impulse};
  nlohmann::json j = physics_summary(fin, totals, !spec.read_data.has_value(), spec.init.seed, spec.histogram_bins,
                                     overlap_tolerance(fin, std::numeric_limits<double>::epsilon()));
  j["engine"] = "event";
  add_energy_summary(j, e0, u0, potential_energy(fin, spec.event.gravity), spec.event.restitution,
                     spec.event.contact_time, spec.event.gravity);
  j["sim_time"] = c.sim_time;
  j["equilibrate_time"] = spec.equilibrate_time;
  j["blocks"] = spec.blocks;
  j["cells_per_dim"] = engine.cells_per_dim();
  j["scene_kernel"] = engine.scene_kernel();
  j["precision"] = "double";
  j["loop_cpu_seconds"] = cpu;
  j["cell_crossings"] = c.cell_crossings;
  j["neighbour_list_rebuilds"] = c.neighbour_list_rebuilds;
  j["neighbour_shell"] = engine.shell();
  j["stale_events"] = c.stale_events;
  j["events"] = c.events;
  j["full_predictions"] = c.full_predictions;
  j["collisions_per_second"] = cpu > 0 ? double(c.collisions) / cpu : 0.0;
  j["events_per_second"] = cpu > 0 ? double(c.events) / cpu : 0.0;
  j["cpu_seconds_per_unit_time"] = c.sim_time > 0 ? cpu / c.sim_time : 0.0;
  j["collision_rate_error"] = rate_err;
  j["compressibility_factor_error"] = z_err;
  if (tracker) j["track"] = tracker->summary();
  commit_outputs(j, fin, spec.write_data, "hardsphere state after event-driven time " + std::to_string(c.sim_time),
                 dump, json_file, tracker ? &tracker->file() : nullptr);
  return j;
}

}  // namespace hardsphere
