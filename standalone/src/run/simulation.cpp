#include "hardsphere/simulation.hpp"

#include <cmath>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>

#include "hardsphere/atomic_file.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/run_summary.hpp"
#include "hardsphere/scene_limits.hpp"
#include "io/tracker.hpp"

namespace hardsphere {

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

namespace {
double rounding_epsilon(Precision p) {
  return p == Precision::Float ? double(std::numeric_limits<float>::epsilon()) : std::numeric_limits<double>::epsilon();
}
}  // namespace

ParticleSystem initial_state(const RunSpec& spec) {
  // A state this program wrote may overlap by the rounding of the engine that made it.
  if (spec.read_data) return read_data(*spec.read_data, spec.periodic, rounding_epsilon(spec.precision));
  InitSpec init = spec.init;
  for (int d = 0; d < 3; ++d) init.box.periodic[d] = spec.periodic[d];
  return make_initial_state(init);
}

void check_outputs(const RunSpec& spec) {
  std::vector<std::pair<std::string, std::string>> out;
  if (spec.json) out.emplace_back("--json", *spec.json);
  if (spec.write_data) out.emplace_back("--write-data", *spec.write_data);
  if (spec.dump) out.emplace_back("--dump", *spec.dump);
  if (spec.track_file) out.emplace_back("--track-file", *spec.track_file);
  check_output_paths(out);
  if (spec.track_id.has_value() != spec.track_file.has_value())
    throw InputError("--track and --track-file go together: give both (and --track-every)");
}

nlohmann::json run_simulation(const RunSpec& spec) {
  if (spec.engine == Engine::Event) return run_event_simulation(spec);
  check_outputs(spec);  // before anything runs or is created, for library callers as for the CLI
  if (spec.steps < 0) throw InputError("steps = " + std::to_string(spec.steps) + " must be >= 0");
  if (spec.equilibrate < 0) throw InputError("equilibrate = " + std::to_string(spec.equilibrate) + " must be >= 0");
  if (spec.dump && spec.dump_every < 1)
    throw InputError("dump every = " + std::to_string(spec.dump_every) + " must be >= 1");
  if (spec.histogram_bins < 1)
    throw InputError("--histogram-bins " + std::to_string(spec.histogram_bins) + " must be >= 1");

  ParticleSystem sys = initial_state(spec);
  StepperConfig cfg = spec.stepper;
  cfg.max_particle_steps = spec.work_limit;
  cfg.count_per_sphere = cfg.count_per_sphere || spec.track_id.has_value();
  auto engine = make_stepper(sys, cfg, spec.precision);
  // Refuse up front what the work limit would stop later (the engine also checks as it runs).
  const double steps = double(spec.steps) + double(spec.equilibrate);
  // Flights between walls barely wider than a sphere bounce many times per step: refuse steps
  // that would run into the per-step event limit, and count the bounces as work.
  const double bounces = wall_bounce_rate(sys) * spec.stepper.dt;
  if (bounces > double(spec.stepper.max_events_per_step)) {
    std::ostringstream m;
    m << "spheres between walls barely wider than them would bounce " << bounces
      << " times per step of dt = " << spec.stepper.dt << ", more than the limit of "
      << spec.stepper.max_events_per_step << " events per step; use a smaller --dt or wider walls";
    throw InputError(m.str());
  }
  const double work = double(sys.size()) * steps * double(engine->substeps_per_step()) + bounces * steps;
  if (work > spec.work_limit) {
    std::ostringstream m;
    m << "the run would take " << work << " particle-steps (" << sys.size() << " spheres, "
      << spec.steps + spec.equilibrate << " steps";
    if (engine->substeps_per_step() > 1)
      m << " of " << engine->substeps_per_step() << " sub-steps each: with dt = " << spec.stepper.dt
        << " the fastest sphere moves more than half the pair-list skin (" << engine->skin() << ") per step";
    m << "), more than the limit of " << spec.work_limit << "; use fewer steps"
      << (engine->substeps_per_step() > 1 ? " or a smaller dt" : "");
    throw InputError(m.str());
  }
  // The tracker samples a whole number of steps apart, so every row is at a step's end.
  std::optional<Tracker> tracker;
  std::int64_t track_steps = 0;
  if (spec.track_id) {
    const double ratio = spec.track_every / spec.stepper.dt;
    track_steps = std::llround(ratio);
    if (!(std::isfinite(ratio) && ratio >= 0.5 && std::abs(ratio - double(track_steps)) <= 1e-9 * ratio)) {
      std::ostringstream m;
      m << "--track-every " << spec.track_every << " is not a whole number of steps of --dt " << spec.stepper.dt;
      throw InputError(m.str());
    }
    tracker.emplace(*spec.track_file, engine->state(), *spec.track_id, spec.track_every,
                    double(spec.steps) * spec.stepper.dt, "stepper");
  }
  // Output files are opened (as temporaries) before the long part, so an unwritable path fails fast.
  std::optional<DumpWriter> dump;
  if (spec.dump) dump.emplace(*spec.dump);
  std::optional<AtomicFile> json_file;
  if (spec.json && *spec.json != "-") json_file.emplace(*spec.json);

  if (spec.equilibrate > 0) {
    engine->run(spec.equilibrate);
    sys = engine->state();
  }
  engine->reset_counters();
  const double e0 = kinetic_energy(sys);
  const double u0 = potential_energy(sys, spec.stepper.gravity);
  const Vec3d p0 = total_momentum(sys);

  double cpu = 0;
  std::int64_t done = 0;
  if (dump) dump->write_frame(0, sys);
  if (tracker) tracker->write(0.0, engine->sphere(tracker->index()));
  // Splitting the run into chunks changes nothing: the engine carries its whole state across.
  const std::int64_t report_every = spec.progress ? std::max<std::int64_t>(1, spec.steps / 100) : spec.steps;
  std::int64_t next_frame = dump ? std::min(spec.dump_every, spec.steps) : spec.steps;
  std::int64_t next_sample = tracker ? std::min(track_steps, spec.steps) : spec.steps;
  while (done < spec.steps) {
    const std::int64_t chunk = std::min({next_frame - done, next_sample - done, report_every, spec.steps - done});
    const double t0 = process_cpu_seconds();
    engine->run(chunk);
    cpu += process_cpu_seconds() - t0;
    done += chunk;
    if (dump && done == next_frame) {
      dump->write_frame(done, engine->state());
      next_frame = std::min(next_frame + spec.dump_every, spec.steps);
    }
    if (tracker && done == next_sample) {
      if (done % track_steps == 0) tracker->write(double(done) * spec.stepper.dt, engine->sphere(tracker->index()));
      next_sample = std::min(next_sample + track_steps, spec.steps);
    }
    if (spec.progress) spec.progress(double(done) / double(spec.steps), engine->counters().sim_time);
  }
  const ParticleSystem fin = engine->state();
  const StepCounters& c = engine->counters();

  RunTotals totals{e0, p0, c.sim_time, c.collisions, c.wall_collisions, c.pair_virial, c.wall_impulse};
  nlohmann::json j = physics_summary(fin, totals, !spec.read_data.has_value(), spec.init.seed, spec.histogram_bins,
                                     overlap_tolerance(fin, rounding_epsilon(spec.precision)));
  j["engine"] = "stepper";
  add_energy_summary(j, e0, u0, potential_energy(fin, spec.stepper.gravity), spec.stepper.restitution,
                     spec.stepper.contact_time, spec.stepper.gravity);
  j["steps"] = c.steps;
  j["equilibrate_steps"] = spec.equilibrate;
  j["dt"] = spec.stepper.dt;
  j["sim_time"] = c.sim_time;
  j["cells_per_dim"] = engine->cells_per_dim();
  j["skin"] = engine->skin();
  j["scene_kernel"] = engine->scene_kernel();
  j["detect"] = engine->sweep_detection() ? "sweep" : "overlap";  // the mode in use (auto resolved)
  j["precision"] = spec.precision == Precision::Float ? "float" : "double";
  j["loop_cpu_seconds"] = cpu;
  j["particle_steps_per_second"] = cpu > 0 ? double(fin.size()) * double(c.steps) / cpu : 0.0;
  j["list_rebuilds"] = c.rebuilds;
  j["unresolved_steps"] = c.unresolved_steps;
  if (c.unresolved_steps > 0)
    j["warnings"].push_back(std::to_string(c.unresolved_steps) + " steps stopped at the limit of " +
                            std::to_string(spec.stepper.max_events_per_step) +
                            " contact events per step with contacts left unresolved (spheres may overlap): the "
                            "spheres are jammed or collapsing; use a smaller --dt or a less dense state");
  j["substeps"] = c.substeps;
  j["step_cuts"] = c.step_cuts;
  if (!engine->sweep_detection()) {
    // Overlap detection misses grazes, more of them the further spheres move per step.
    double v2 = 0, dmin = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < fin.size(); ++i)
      v2 += dot(fin.vel[i], fin.vel[i]), dmin = std::min(dmin, 2 * fin.radius[i]);
    const double move = fin.size() ? std::sqrt(v2 / double(fin.size())) * spec.stepper.dt : 0.0;
    if (move > kOverlapDetectionLimit * dmin) {
      std::ostringstream m;
      m << "--detect overlap with steps that move a sphere at the rms speed by " << move / dmin
        << " diameters (more than " << kOverlapDetectionLimit
        << "): grazes within a step are missed (0.5-0.8% of the collisions at 0.14 diameters, more for longer "
           "steps); use --detect sweep or auto";
      j["warnings"].push_back(m.str());
    }
  }
  if (tracker) j["track"] = tracker->summary();
  commit_outputs(j, fin, spec.write_data, "hardsphere state after " + std::to_string(c.steps) + " steps", dump,
                 json_file, tracker ? &tracker->file() : nullptr);
  return j;
}

}  // namespace hardsphere
