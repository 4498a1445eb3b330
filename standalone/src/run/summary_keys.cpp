// The engines' own keys of the run summary and their totals, shared by the CLI's run driver and
// the Python module so that both report the same numbers under the same names.
#include "hardsphere/observables.hpp"
#include "hardsphere/simulation.hpp"

namespace hardsphere {

void add_shape_summary(nlohmann::json& j, const Physics& physics, const StepCounters& c) {
  if (physics.shapes.empty()) return;
  nlohmann::json walls = nlohmann::json::array();
  for (std::size_t k = 0; k < physics.shapes.size(); ++k) {
    const WallShapeTotals t = k < c.shapes.size() ? c.shapes[k] : WallShapeTotals{};
    walls.push_back({{"wall", describe(physics.shapes[k])},
                     {"collisions", t.collisions},
                     {"resting_contacts", t.resting_contacts},
                     {"work", t.work}});
  }
  j["shaped_walls"] = walls;
  j["wall_work"] = c.wall_work;
}

void add_stepper_summary(nlohmann::json& j, const StepperBase& engine, const StepperConfig& cfg, Precision precision,
                         const ParticleSystem& fin, std::int64_t equilibrate_steps, double cpu) {
  const StepCounters& c = engine.counters();
  j["steps"] = c.steps;
  j["equilibrate_steps"] = equilibrate_steps;
  j["dt"] = cfg.dt;
  j["sim_time"] = c.sim_time;
  j["cells_per_dim"] = engine.cells_per_dim();
  j["skin"] = engine.skin();
  j["scene_kernel"] = engine.scene_kernel();
  j["detect"] = engine.sweep_detection() ? "sweep" : "overlap";  // the mode in use (auto resolved)
  j["precision"] = precision == Precision::Float ? "float" : "double";
  j["particle_steps_per_second"] = cpu > 0 ? double(fin.size()) * double(c.steps) / cpu : 0.0;
  j["list_rebuilds"] = c.rebuilds;
  j["unresolved_steps"] = c.unresolved_steps;
  j["substeps"] = c.substeps;
  j["step_cuts"] = c.step_cuts;
  add_stepper_warnings(j, engine, cfg, fin);
}

void add_event_summary(nlohmann::json& j, const EventEngine& engine, double equilibrate_time, double cpu) {
  const EventCounters& c = engine.counters();
  j["sim_time"] = c.sim_time;
  j["equilibrate_time"] = equilibrate_time;
  j["cells_per_dim"] = engine.cells_per_dim();
  j["scene_kernel"] = engine.scene_kernel();
  j["precision"] = "double";
  j["cell_crossings"] = c.cell_crossings;
  j["neighbour_list_rebuilds"] = c.neighbour_list_rebuilds;
  j["neighbour_shell"] = engine.shell();
  j["stale_events"] = c.stale_events;
  j["events"] = c.events;
  j["full_predictions"] = c.full_predictions;
  j["collisions_per_second"] = cpu > 0 ? double(c.collisions) / cpu : 0.0;
  j["events_per_second"] = cpu > 0 ? double(c.events) / cpu : 0.0;
  j["cpu_seconds_per_unit_time"] = c.sim_time > 0 ? cpu / c.sim_time : 0.0;
}

nlohmann::json run_summary(const ParticleSystem& initial, const ParticleSystem& fin, const RunTotals& totals,
                           const Physics& physics, const SummaryOrigin& origin, const std::string& engine,
                           double rounding_eps, double loop_cpu) {
  nlohmann::json j = physics_summary(fin, totals, origin.com_removed, origin.seed, origin.histogram_bins,
                                     overlap_tolerance(fin, rounding_eps));
  j["engine"] = engine;
  add_energy_summary(j, totals.kinetic_energy_initial, potential_energy(initial, physics.gravity),
                     potential_energy(fin, physics.gravity), physics);
  add_rough_summary(j, initial, fin, totals, physics);
  add_wall_summary(j, fin.box, totals, physics);
  if (const std::size_t k = fin.kinematic_count()) {  // only then, so other summaries keep their keys
    j["kinematic_spheres"] = k;
    j["kinematic_collisions"] = totals.kinematic_collisions;
    j["kinematic_work"] = totals.kinematic_work;
  }
  j["loop_cpu_seconds"] = loop_cpu;
  return j;
}

namespace {
template <class Counters>
RunTotals totals_of(const Counters& c, double kinetic0, const Vec3d& momentum0) {
  RunTotals t;
  t.kinetic_energy_initial = kinetic0;
  t.momentum_initial = momentum0;
  t.sim_time = c.sim_time;
  static_cast<CollisionTotals&>(t) = collision_totals(c);
  return t;
}
}  // namespace

RunTotals run_totals(const StepCounters& c, double kinetic0, const Vec3d& momentum0) {
  return totals_of(c, kinetic0, momentum0);
}
RunTotals run_totals(const EventCounters& c, double kinetic0, const Vec3d& momentum0) {
  return totals_of(c, kinetic0, momentum0);
}

}  // namespace hardsphere
