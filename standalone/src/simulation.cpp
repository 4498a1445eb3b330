#include "hardsphere/simulation.hpp"

#include <ctime>
#include <fstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/observables.hpp"

namespace hardsphere {

double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

ParticleSystem initial_state(const RunSpec& spec) {
  if (spec.read_data) return read_data(*spec.read_data, spec.periodic);
  InitSpec init = spec.init;
  for (int d = 0; d < 3; ++d) init.box.periodic[d] = spec.periodic[d];
  return make_initial_state(init);
}

namespace {

nlohmann::json vec_json(Vec3d v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

nlohmann::json run_simulation(const RunSpec& spec) {
  if (spec.engine == Engine::Event) return run_event_simulation(spec);
  if (spec.steps < 0) throw InputError("steps = " + std::to_string(spec.steps) + " must be >= 0");
  if (spec.equilibrate < 0) throw InputError("equilibrate = " + std::to_string(spec.equilibrate) + " must be >= 0");
  if (spec.dump && spec.dump_every < 1) throw InputError("dump every = " + std::to_string(spec.dump_every) + " must be >= 1");
  if (spec.histogram_bins < 1) throw InputError("histogram bins must be >= 1");

  ParticleSystem sys = initial_state(spec);
  auto engine = make_stepper(sys, spec.stepper, spec.precision);
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
  const Vec3d p0 = total_momentum(sys);

  double cpu = 0;
  std::int64_t done = 0;
  if (dump) dump->write_frame(0, sys);
  while (done < spec.steps) {
    const std::int64_t chunk = dump ? std::min(spec.dump_every, spec.steps - done) : spec.steps - done;
    const double t0 = process_cpu_seconds();
    engine->run(chunk);
    cpu += process_cpu_seconds() - t0;
    done += chunk;
    if (dump) dump->write_frame(done, engine->state());
  }
  const ParticleSystem fin = engine->state();
  const StepCounters& c = engine->counters();

  const double e1 = kinetic_energy(fin);
  const double t_final = temperature(fin);
  const double t_mean = 0.5 * (2 * e0 / (3.0 * double(sys.size())) + t_final);
  double v2max = 0;
  for (const auto& v : fin.vel) v2max = std::max(v2max, dot(v, v));
  const Histogram h = speed_histogram(fin, spec.histogram_bins, std::max(1e-300, 1.0000001 * std::sqrt(v2max)));
  const double z = compressibility_factor(c.pair_virial, c.sim_time, fin.size(), t_mean);

  nlohmann::json j;
  j["engine"] = "stepper";
  j["n"] = fin.size();
  j["packing_fraction"] = fin.packing_fraction();
  j["box"] = {{"lo", fin.box.lo}, {"hi", fin.box.hi}, {"boundary", boundary_string(fin.box.periodic)}};
  j["steps"] = c.steps;
  j["equilibrate_steps"] = spec.equilibrate;
  j["dt"] = spec.stepper.dt;
  j["sim_time"] = c.sim_time;
  j["cells_per_dim"] = engine->cells_per_dim();
  j["skin"] = engine->skin();
  j["scene_kernel"] = engine->scene_kernel();
  j["precision"] = spec.precision == Precision::Float ? "float" : "double";
  j["loop_cpu_seconds"] = cpu;
  j["particle_steps_per_second"] = cpu > 0 ? double(fin.size()) * double(c.steps) / cpu : 0.0;
  j["collisions"] = c.collisions;
  j["wall_collisions"] = c.wall_collisions;
  j["collision_rate_per_particle"] = c.sim_time > 0 ? 2.0 * double(c.collisions) / (double(fin.size()) * c.sim_time) : 0.0;
  j["list_rebuilds"] = c.rebuilds;
  j["unresolved_steps"] = c.unresolved_steps;
  j["kinetic_energy_initial"] = e0;
  j["kinetic_energy_final"] = e1;
  j["energy_rel_drift"] = e0 > 0 ? (e1 - e0) / e0 : 0.0;
  j["momentum_initial"] = vec_json(p0);
  j["momentum_final"] = vec_json(total_momentum(fin));
  j["temperature"] = t_final;
  j["com_removed"] = !spec.read_data.has_value();
  j["pair_virial"] = c.pair_virial;
  j["compressibility_factor"] = z;
  j["pressure"] = z * double(fin.size()) * t_mean / fin.box.volume();
  // Walls: the pressure on each wall pair is the momentum it received per area and time.
  nlohmann::json wall_p = nlohmann::json::array();
  for (int d = 0; d < 3; ++d) {
    if (fin.box.periodic[d] || !(c.sim_time > 0)) wall_p.push_back(nullptr);
    else wall_p.push_back(c.wall_impulse[d] / (2.0 * fin.box.volume() / fin.box.length(d) * c.sim_time));
  }
  j["wall_pressure"] = wall_p;
  j["max_overlap"] = max_overlap(fin);
  j["speed_ks_distance"] = maxwell_ks_distance(fin, t_final);
  j["speed_histogram"] = {{"lo", h.lo}, {"hi", h.hi}, {"counts", h.counts}};
  j["seed"] = spec.init.seed;

  if (spec.write_data) write_data(*spec.write_data, fin, "hardsphere state after " + std::to_string(c.steps) + " steps");
  if (dump) dump->commit();
  if (json_file) {
    json_file->stream() << j.dump(2) << '\n';
    json_file->commit();
  }
  return j;
}

}  // namespace hardsphere
