// One complete run as the command line performs it, for either engine: outputs checked, initial
// state, equilibration, the measured run with dumps and tracker rows, the summary, and the commit
// of every output only when all of it succeeded.
#include <ctime>
#include <limits>

#include "hardsphere/atomic_file.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/run_summary.hpp"
#include "hardsphere/simulation.hpp"
#include "io/tracker.hpp"
#include "run/engine_run.hpp"

namespace hardsphere {

Engine parse_engine(const std::string& s) {
  if (s == "stepper") return Engine::Stepper;
  if (s == "event") return Engine::Event;
  throw InputError("unknown engine '" + s + "' (expected stepper or event)");
}

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void set_kinematic_types(ParticleSystem& sys, const std::vector<int>& types, const std::string& option,
                         const std::string& source) {
  if (types.empty()) return;
  sys.kinematic.assign(sys.size(), 0);
  for (const int t : types) {
    bool found = false;
    for (std::size_t i = 0; i < sys.size(); ++i)
      if (sys.type[i] == t) sys.kinematic[i] = 1, found = true;
    if (!found)
      throw InputError(option + " " + std::to_string(t) + ": no atom of type " + std::to_string(t) + " in " + source);
  }
}

ParticleSystem initial_state(const RunSpec& spec, std::vector<std::string>* notes) {
  // A state this program wrote may overlap by the rounding of the engine that made it.
  if (spec.read_data) {
    if (spec.kinematic_types.empty())
      return read_data(*spec.read_data, spec.periodic, rounding_epsilon(spec.precision), notes);
    // Kinematic spheres of a lattice base may overlap: the file is read without the pair check,
    // which set_kinematic_types() makes knowing which pairs may.
    ParticleSystem sys = read_data(*spec.read_data, spec.periodic, rounding_epsilon(spec.precision), notes, false);
    set_kinematic_types(sys, spec.kinematic_types, "--kinematic-types", *spec.read_data);
    validate_and_wrap(sys, *spec.read_data, &sys.source_line, rounding_epsilon(spec.precision));
    return sys;
  }
  if (!spec.kinematic_types.empty())
    throw InputError("--kinematic-types needs --read-data: a generated state has atoms of type 1 only");
  InitSpec init = spec.init;
  if (spec.physics.rough()) {  // rotation at the translational temperature unless given
    init.inertia = spec.physics.inertia;
    if (!init.rotational_temperature)
      init.rotational_temperature = init.speed ? init.mass * *init.speed * *init.speed / 3 : init.temperature;
  } else {
    init.rotational_temperature.reset();
  }
  for (int d = 0; d < 3; ++d) init.box.periodic[d] = spec.periodic[d];
  init.walls = spec.physics.shapes;
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
  check_outputs(spec);  // before anything runs or is created, for library callers as for the CLI
  if (spec.histogram_bins < 1)
    throw InputError("--histogram-bins " + std::to_string(spec.histogram_bins) + " must be >= 1");
  const std::unique_ptr<EngineRun> engine =
      spec.engine == Engine::Event ? make_event_run(spec) : make_stepper_run(spec);

  std::vector<std::string> notes;  // sections of the data file that were skipped
  ParticleSystem sys = initial_state(spec, &notes);
  engine->start(sys);
  std::optional<TransportRun> transport;  // refused before the run when the scene has no coefficients
  if (spec.transport) transport.emplace(spec, sys, engine->measured_time(), engine->time_quantum());
  std::optional<Tracker> tracker;
  if (spec.track_id) {
    engine->check_track_every(spec.track_every);
    tracker.emplace(*spec.track_file, engine->state(), *spec.track_id, spec.track_every, engine->measured_time(),
                    engine->name());
  }
  // Output files are opened (as temporaries) before the long part, so an unwritable path fails fast.
  std::optional<DumpWriter> dump;
  if (spec.dump) dump.emplace(*spec.dump, spec.physics.rough());
  std::optional<AtomicFile> json_file;
  if (spec.json && *spec.json != "-") json_file.emplace(*spec.json);

  if (engine->equilibrate()) sys = engine->state();
  engine->reset_counters();
  const double e0 = kinetic_energy(sys);
  const Vec3d p0 = total_momentum(sys);
  if (dump) dump->write_frame(0, sys);
  const double cpu = engine->measure({dump ? &*dump : nullptr, tracker ? &*tracker : nullptr,
                                      spec.progress ? &spec.progress : nullptr, transport ? &*transport : nullptr});

  const ParticleSystem fin = engine->state();
  const RunTotals totals = engine->totals(e0, p0);
  nlohmann::json j =
      run_summary(sys, fin, totals, spec.physics, {!spec.read_data.has_value(), spec.init.seed, spec.histogram_bins},
                  engine->name(), engine->rounding_epsilon(), cpu);
  for (auto n = notes.rbegin(); n != notes.rend(); ++n) j["warnings"].insert(j["warnings"].begin(), *n);
  engine->add_summary(j, fin, cpu);
  if (transport) transport->add_summary(j);
  if (tracker) j["track"] = tracker->summary();
  if (spec.report) spec.report(j);
  commit_outputs(j, fin, spec.write_data, engine->final_title(), dump, json_file, tracker ? &tracker->file() : nullptr);
  return j;
}

}  // namespace hardsphere
