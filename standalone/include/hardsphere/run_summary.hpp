#pragma once
//! The JSON keys every engine reports the same way (state, conservation, pressure, speeds),
//! and the final commit of a run's output files. Engines add their own keys on top.
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "hardsphere/collision_totals.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"

namespace hardsphere {

//! What an engine measured over the timed part of a run.
struct RunTotals : CollisionTotals {
  double kinetic_energy_initial = 0;
  Vec3d momentum_initial;
  double sim_time = 0;
};

//! Keys n, packing_fraction, box, collisions, wall_collisions, resting_contacts, collision_rate_per_particle,
//! kinetic_energy_*, energy_rel_drift, momentum_*, temperature, com_removed, pair_virial,
//! compressibility_factor, pressure, wall_pressure, max_overlap, speed_ks_distance,
//! speed_histogram, seed, overlap_tolerance, warnings (documented in docs/cli.md). T in Z is the mean
//! of initial and final T. A final overlap above `overlap_tolerance` (the rounding level of the
//! engine's arithmetic, see overlap_tolerance()) adds a warning naming its cause and remedy.
nlohmann::json physics_summary(const ParticleSystem& final_state, const RunTotals& totals, bool com_removed,
                               std::uint64_t seed, int histogram_bins, double overlap_tolerance);

//! Adds the run's restitution, contact time and gravity, the potential energies before and after
//! (-sum m g.(x - lo)), and replaces energy_rel_drift by that of kinetic + potential energy; the
//! energy inelastic collisions took is dissipated_energy.
void add_energy_summary(nlohmann::json& j, double kinetic0, double potential0, double potential1,
                        const Physics& physics);

//! Rough scenes (physics.rough()): adds tangential_restitution, friction (null: no Coulomb limit),
//! inertia, the translational (centre-of-mass frame) and rotational temperatures and kinetic
//! energies of `initial` and `final_state`, the energy dissipated by channel, and makes
//! dissipated_energy and energy_rel_drift count the rotational energy too. Call after
//! add_energy_summary().
void add_rough_summary(nlohmann::json& j, const ParticleSystem& initial, const ParticleSystem& final_state,
                       const RunTotals& totals, const Physics& physics);

//! Walls with laws of their own (physics.wall_laws()): adds wall_laws, each face with a wall and
//! its restitution, tangential_restitution and friction (null: smooth spheres, or no Coulomb
//! limit), and what the walls took: wall_dissipated_energy_normal (restitution and the resting
//! contacts' net), wall_dissipated_energy_tangential (friction). Default walls add no key.
void add_wall_summary(nlohmann::json& j, const Box& box, const RunTotals& totals, const Physics& physics);

//! Writes the JSON file and the final data file, and commits them with the dump and `track`
//! (a tracker's file, may be null): only after success, and all together (commit_together), so
//! an error leaves none of them.
void commit_outputs(const nlohmann::json& summary, const ParticleSystem& final_state,
                    const std::optional<std::string>& write_data_path, const std::string& title,
                    std::optional<DumpWriter>& dump, std::optional<AtomicFile>& json_file, AtomicFile* track = nullptr);

}  // namespace hardsphere
