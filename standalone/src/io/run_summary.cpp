#include "hardsphere/run_summary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "hardsphere/box.hpp"
#include "hardsphere/observables.hpp"

namespace hardsphere {

namespace {
nlohmann::json vec_json(Vec3d v) { return nlohmann::json::array({v.x, v.y, v.z}); }
}  // namespace

nlohmann::json physics_summary(const ParticleSystem& fin, const RunTotals& t, bool com_removed, std::uint64_t seed,
                               int histogram_bins, double tolerance) {
  const std::size_t n = fin.size();
  const double e0 = t.kinetic_energy_initial, e1 = kinetic_energy(fin);
  const double t_final = temperature(fin);
  const double t_mean = n ? 0.5 * (2 * e0 / (3.0 * double(n)) + t_final) : 0.0;
  double v2max = 0;
  for (const auto& v : fin.vel) v2max = std::max(v2max, dot(v, v));
  const Histogram h = speed_histogram(fin, histogram_bins, std::max(1e-300, 1.0000001 * std::sqrt(v2max)));
  const double z = compressibility_factor(t.pair_virial, t.sim_time, n, t_mean);

  nlohmann::json j;
  j["n"] = n;
  j["packing_fraction"] = fin.packing_fraction();
  j["box"] = {{"lo", fin.box.lo}, {"hi", fin.box.hi}, {"boundary", boundary_string(fin.box.periodic)}};
  j["collisions"] = t.collisions;
  j["wall_collisions"] = t.wall_collisions;
  j["resting_contacts"] = t.resting_contacts;
  j["collision_rate_per_particle"] = t.sim_time > 0 && n ? 2.0 * double(t.collisions) / (double(n) * t.sim_time) : 0.0;
  j["kinetic_energy_initial"] = e0;
  j["kinetic_energy_final"] = e1;
  j["energy_rel_drift"] = e0 > 0 ? (e1 - e0) / e0 : 0.0;
  j["momentum_initial"] = vec_json(t.momentum_initial);
  j["momentum_final"] = vec_json(total_momentum(fin));
  j["temperature"] = t_final;
  j["com_removed"] = com_removed;
  j["pair_virial"] = t.pair_virial;
  j["compressibility_factor"] = z;
  j["pressure"] = z * double(n) * t_mean / fin.box.volume();
  // Walls: the pressure on each wall pair is the momentum it received per area and time.
  nlohmann::json wall_p = nlohmann::json::array();
  for (int d = 0; d < 3; ++d) {
    if (fin.box.periodic[d] || !(t.sim_time > 0))
      wall_p.push_back(nullptr);
    else
      wall_p.push_back(t.wall_impulse[d] / (2.0 * fin.box.volume() / fin.box.length(d) * t.sim_time));
  }
  j["wall_pressure"] = wall_p;
  const double overlap = max_overlap(fin);
  j["max_overlap"] = overlap;
  j["overlap_tolerance"] = tolerance;
  nlohmann::json warnings = nlohmann::json::array();
  if (overlap > tolerance) {
    std::ostringstream m;
    m << "spheres overlap by up to " << overlap << " at the end of the run (rounding accounts for " << tolerance
      << "): contacts were missed, e.g. grazes or fast spheres passing through each other within one step under "
         "--detect overlap; rerun with --detect sweep or a smaller --dt";
    warnings.push_back(m.str());
  }
  j["warnings"] = warnings;
  j["speed_ks_distance"] = maxwell_ks_distance(fin, t_final);
  j["speed_histogram"] = {{"lo", h.lo}, {"hi", h.hi}, {"counts", h.counts}};
  j["seed"] = seed;
  return j;
}

void commit_outputs(const nlohmann::json& summary, const ParticleSystem& fin,
                    const std::optional<std::string>& write_data_path, const std::string& title,
                    std::optional<DumpWriter>& dump, std::optional<AtomicFile>& json_file, AtomicFile* track) {
  // Everything is written to temporaries first and renamed together at the end, so an error
  // in any of them (or a signal) leaves none of the outputs behind.
  std::optional<AtomicFile> data_file;
  if (write_data_path) {
    data_file.emplace(*write_data_path);
    write_data(data_file->stream(), fin, title);
  }
  if (json_file) json_file->stream() << summary.dump(2) << '\n';
  commit_together(
      {data_file ? &*data_file : nullptr, dump ? &dump->file() : nullptr, json_file ? &*json_file : nullptr, track});
}

void add_rough_summary(nlohmann::json& j, const ParticleSystem& initial, const ParticleSystem& fin, const RunTotals& t,
                       const Physics& physics) {
  if (!physics.rough()) return;
  const double q = physics.inertia;
  const double k0 = kinetic_energy(initial), k1 = kinetic_energy(fin);
  const double r0 = rotational_kinetic_energy(initial, q), r1 = rotational_kinetic_energy(fin, q);
  j["tangential_restitution"] = physics.tangential_restitution;
  if (std::isfinite(physics.friction))
    j["friction"] = physics.friction;
  else
    j["friction"] = nullptr;
  j["inertia"] = q;
  j["temperature_translational_initial"] = translational_temperature(initial);
  j["temperature_translational_final"] = translational_temperature(fin);
  j["temperature_rotational_initial"] = rotational_temperature(initial, q);
  j["temperature_rotational_final"] = rotational_temperature(fin, q);
  j["kinetic_energy_translational_initial"] = k0;
  j["kinetic_energy_translational_final"] = k1;
  j["kinetic_energy_rotational_initial"] = r0;
  j["kinetic_energy_rotational_final"] = r1;
  j["dissipated_energy_normal"] = t.dissipated_normal;
  j["dissipated_energy_tangential"] = t.dissipated_tangential;
  const double e0 = k0 + r0 + j["potential_energy_initial"].get<double>();
  const double e1 = k1 + r1 + j["potential_energy_final"].get<double>();
  j["dissipated_energy"] = e0 - e1;
  j["energy_rel_drift"] = e0 > 0 ? (e1 - e0) / e0 : 0.0;
}

void add_wall_summary(nlohmann::json& j, const Box& box, const RunTotals& t, const Physics& physics) {
  if (!physics.wall_laws() && physics.shapes.empty()) return;
  nlohmann::json laws = nlohmann::json::object();
  for (int f = 0; f < 6; ++f) {
    if (box.periodic[std::size_t(f / 2)]) continue;
    nlohmann::json face{{"restitution", physics.walls[std::size_t(f)].restitution}};
    const double beta = physics.wall_tangential_restitution(f), mu = physics.wall_friction(f);
    face["tangential_restitution"] = physics.rough() ? nlohmann::json(beta) : nlohmann::json(nullptr);
    face["friction"] = physics.rough() && std::isfinite(mu) ? nlohmann::json(mu) : nlohmann::json(nullptr);
    laws[kFaceNames[std::size_t(f)]] = face;
  }
  j["wall_laws"] = laws;
  j["wall_dissipated_energy_normal"] = t.wall_dissipated_normal;
  j["wall_dissipated_energy_tangential"] = t.wall_dissipated_tangential;
}

void add_energy_summary(nlohmann::json& j, double kinetic0, double potential0, double potential1,
                        const Physics& physics) {
  const double e0 = kinetic0 + potential0, e1 = j["kinetic_energy_final"].get<double>() + potential1;
  j["restitution"] = physics.restitution;
  j["contact_time"] = physics.contact_time;
  j["gravity"] = physics.gravity;
  j["potential_energy_initial"] = potential0;
  j["potential_energy_final"] = potential1;
  j["dissipated_energy"] = e0 - e1;
  j["energy_rel_drift"] = e0 > 0 ? (e1 - e0) / e0 : 0.0;
}

}  // namespace hardsphere
