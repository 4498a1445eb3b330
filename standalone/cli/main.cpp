// hardsphere: command-line front end. It only parses options and calls the library.
#include <CLI/CLI.hpp>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/simulation.hpp"

using namespace hardsphere;

namespace {

std::vector<double> parse_list(const std::string& s, const char* what) {
  std::vector<double> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') throw InputError(std::string(what) + " '" + s + "': '" + item + "' is not a number");
    out.push_back(v);
  }
  if (out.size() != 1 && out.size() != 3) throw InputError(std::string(what) + " '" + s + "' needs one value or three (x,y,z)");
  if (out.size() == 1) out = {out[0], out[0], out[0]};
  return out;
}

//! A seed is any whole number 0 .. 2^64-1; strtoull alone would wrap "-1" to 2^64-1.
std::uint64_t parse_seed(const std::string& s) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (s.empty() || !std::isdigit(static_cast<unsigned char>(s[0])) || *end != '\0' || errno == ERANGE)
    throw InputError("--seed '" + s + "' must be a whole number from 0 to 18446744073709551615");
  return v;
}

std::array<int, 3> parse_cells(const std::string& s) {
  if (s == "auto") return {0, 0, 0};
  const auto v = parse_list(s, "--cells");
  std::array<int, 3> k{};
  for (int d = 0; d < 3; ++d) {
    if (!(v[d] >= 1) || v[d] != std::floor(v[d]) || v[d] > 1e6)
      throw InputError("--cells '" + s + "': cell counts must be whole numbers >= 1 (or auto)");
    k[d] = int(v[d]);
  }
  return k;
}

void print_event_summary(const nlohmann::json& j, std::ostream& o) {
  o << "hardsphere: " << j["n"] << " spheres, packing fraction " << j["packing_fraction"].get<double>()
    << ", event-driven for time " << j["sim_time"].get<double>() << " (" << j["scene_kernel"].get<std::string>()
    << ", cells " << j["cells_per_dim"].dump() << ")\n"
    << "  collisions        " << j["collisions"] << " (" << j["collision_rate_per_particle"].get<double>() << " +- "
    << j["collision_rate_error"].get<double>() << " per particle per unit time)\n"
    << "  temperature       " << j["temperature"].get<double>() << "\n"
    << "  Z = PV/NkT        " << j["compressibility_factor"].get<double>() << " +- "
    << j["compressibility_factor_error"].get<double>() << "\n"
    << "  energy drift      " << j["energy_rel_drift"].get<double>() << " (relative)\n"
    << "  max overlap       " << j["max_overlap"].get<double>() << "\n"
    << "  speed KS distance " << j["speed_ks_distance"].get<double>() << " from Maxwell-Boltzmann\n"
    << "  CPU time (loop)   " << j["loop_cpu_seconds"].get<double>() << " s, " << j["collisions_per_second"].get<double>()
    << " collisions/s, " << j["events_per_second"].get<double>() << " events/s\n";
}

void print_summary(const nlohmann::json& j, std::ostream& o) {
  if (j.value("engine", "stepper") == "event") return print_event_summary(j, o);
  o << "hardsphere: " << j["n"] << " spheres, packing fraction " << j["packing_fraction"].get<double>() << ", "
    << j["steps"] << " steps of dt " << j["dt"].get<double>() << " (" << j["scene_kernel"].get<std::string>() << ", cells "
    << j["cells_per_dim"].dump() << ")\n"
    << "  collisions        " << j["collisions"] << " (" << j["collision_rate_per_particle"].get<double>() << " per particle per unit time)\n"
    << "  temperature       " << j["temperature"].get<double>() << "\n"
    << "  Z = PV/NkT        " << j["compressibility_factor"].get<double>() << "\n"
    << "  energy drift      " << j["energy_rel_drift"].get<double>() << " (relative)\n"
    << "  max overlap       " << j["max_overlap"].get<double>() << "\n"
    << "  speed KS distance " << j["speed_ks_distance"].get<double>() << " from Maxwell-Boltzmann\n"
    << "  CPU time (loop)   " << j["loop_cpu_seconds"].get<double>() << " s, "
    << j["particle_steps_per_second"].get<double>() << " particle-steps/s\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hardsphere: time-stepped hard-sphere molecular dynamics with cell lists"};
  app.require_subcommand(1);
  auto* run = app.add_subcommand("run", "run a simulation and report a summary");

  RunSpec spec;
  std::int64_t n = 1000;
  double phi = 0.2;
  std::string box_s, boundary_s = "p", cells_s = "auto", precision_s = "double", init_s = "auto", json_s, detect_s = "auto";
  double init_speed = 0;
  std::string read_data_s, write_data_s, dump_s;

  auto* o_n = run->add_option("--n", n, "number of spheres (default 1000)");
  auto* o_phi = run->add_option("--phi", phi, "packing fraction: sets the cubic box from n (default 0.2)");
  auto* o_box = run->add_option("--box", box_s, "box length L or Lx,Ly,Lz (box from 0 to L)");
  auto* o_radius = run->add_option("--radius", spec.init.radius, "sphere radius (default 0.5)");
  auto* o_mass = run->add_option("--mass", spec.init.mass, "sphere mass (default 1)");
  run->add_option("--boundary", boundary_s, "p (periodic) or w (wall) per axis, e.g. p,p,w (default p)");
  auto* o_t = run->add_option("--temperature", spec.init.temperature, "initial temperature, k_B = 1 (default 1)");
  auto* o_speed = run->add_option("--init-speed", init_speed, "give every sphere this speed, isotropic directions");
  auto* o_init = run->add_option("--init", init_s, "initial positions: auto, random (insertion) or lattice (dense route)");
  std::string seed_s = "1";
  auto* o_seed = run->add_option("--seed", seed_s, "random seed, 0 .. 2^64-1 (default 1)");
  auto* o_dt = run->add_option("--dt", spec.stepper.dt, "time step (default 0.01)");
  auto* o_steps = run->add_option("--steps", spec.steps, "measured steps (default 1000)");
  auto* o_equil = run->add_option("--equilibrate", spec.equilibrate, "steps run first and not measured (default 0)");
  run->add_option("--cells", cells_s, "cells per axis: auto, K or Kx,Ky,Kz (1 = one box, O(N^2))");
  run->add_option("--precision", precision_s, "double or float (default double)");
  auto* o_detect = run->add_option("--detect", detect_s, "contact detection: auto (default: sweep for steps with v_rms dt > 0.1 diameters, else overlap), overlap (a posteriori) or sweep (whole step)");
  std::string engine_s = "stepper";
  double time_s = 0, equilibrate_time_s = 0;
  run->add_option("--engine", engine_s, "stepper (time-stepped, default) or event (exact event-driven)");
  auto* o_time = run->add_option("--time", time_s, "simulated time measured (event engine; stepper: steps = time/dt)");
  auto* o_etime = run->add_option("--equilibrate-time", equilibrate_time_s, "simulated time run first and not measured");
  auto* o_blocks = run->add_option("--blocks", spec.blocks, "event engine: block averages for the error bars (default 20)");
  auto* o_read = run->add_option("--read-data", read_data_s, "start from a LAMMPS data file (atom_style sphere)");
  run->add_option("--write-data", write_data_s, "write the final state as a LAMMPS data file");
  auto* o_dump = run->add_option("--dump", dump_s, "write a LAMMPS text dump");
  auto* o_dump_every = run->add_option("--dump-every", spec.dump_every, "steps between dump frames (default 100)")->needs(o_dump);
  run->add_option("--json", json_s, "write the JSON summary to FILE (- for stdout)");
  run->add_option("--histogram-bins", spec.histogram_bins, "bins of the speed histogram in the JSON (default 40)");
  for (auto* o : {o_n, o_phi, o_box, o_radius, o_mass, o_t, o_speed, o_init, o_seed}) o_read->excludes(o);
  o_t->excludes(o_speed);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  try {
    spec.periodic = parse_boundary(boundary_s);
    spec.stepper.cells = parse_cells(cells_s);
    spec.init.seed = parse_seed(seed_s);
    spec.precision = parse_precision(precision_s);
    spec.stepper.detect = parse_detect(detect_s);
    spec.engine = parse_engine(engine_s);
    if (spec.engine == Engine::Event) {
      for (auto* o : {o_dt, o_steps, o_equil, o_detect, o_dump_every})
        if (o->count()) throw InputError(o->get_name() + " is a stepper option; the event engine runs for --time (simulated time)");
      if (spec.precision != Precision::Double) throw InputError("--precision " + precision_s + ": the event engine runs in double only");
      if (!o_time->count()) throw InputError("--engine event needs --time T (simulated time to run)");
      spec.time = time_s;
      spec.equilibrate_time = equilibrate_time_s;
      spec.event.cells = spec.stepper.cells;
    } else {
      if (o_blocks->count()) throw InputError("--blocks is an event-engine option (use with --engine event)");
      // A bad --dt is reported by the stepper itself; only a valid one converts times to steps.
      const double dt = spec.stepper.dt;
      const bool dt_ok = std::isfinite(dt) && dt > 0;
      if (o_time->count() && dt_ok) {
        if (o_steps->count()) throw InputError("--steps and --time both set the run length; give one");
        if (!(std::isfinite(time_s) && time_s >= 0)) throw InputError("--time " + std::to_string(time_s) + " must be >= 0");
        if (time_s / dt > 1e15) throw InputError("--time " + std::to_string(time_s) + " / --dt is more than 1e15 steps");
        spec.steps = std::llround(time_s / dt);
      }
      if (o_etime->count() && dt_ok) {
        if (o_equil->count()) throw InputError("--equilibrate and --equilibrate-time both set the equilibration; give one");
        if (!(std::isfinite(equilibrate_time_s) && equilibrate_time_s >= 0))
          throw InputError("--equilibrate-time " + std::to_string(equilibrate_time_s) + " must be >= 0");
        if (equilibrate_time_s / dt > 1e15) throw InputError("--equilibrate-time / --dt is more than 1e15 steps");
        spec.equilibrate = std::llround(equilibrate_time_s / dt);
      }
    }
    if (!read_data_s.empty()) spec.read_data = read_data_s;
    if (!write_data_s.empty()) spec.write_data = write_data_s;
    if (!dump_s.empty()) spec.dump = dump_s;
    if (!json_s.empty()) spec.json = json_s;
    if (!spec.read_data) {
      spec.init.n = n;
      spec.init.method = parse_init_method(init_s);
      if (o_speed->count()) spec.init.speed = init_speed;
      const double r = spec.init.radius;
      if (!(std::isfinite(r) && r > 0)) throw InputError("--radius " + std::to_string(r) + " must be positive and finite");
      if (n < 1) throw InputError("--n " + std::to_string(n) + " must be >= 1");
      std::array<double, 3> len{};
      if (o_box->count()) {
        if (o_phi->count()) throw InputError("--phi and --box both set the box size; give one");
        const auto v = parse_list(box_s, "--box");
        for (int d = 0; d < 3; ++d) len[d] = v[d];
      } else {
        if (!(std::isfinite(phi) && phi > 0)) throw InputError("--phi " + std::to_string(phi) + " must be positive");
        const double l = std::cbrt(double(n) * 4.0 / 3.0 * M_PI * r * r * r / phi);
        len = {l, l, l};
      }
      spec.init.box = Box::from_lengths(len, spec.periodic);
    }
    const auto summary = run_simulation(spec);
    for (const auto& w : summary["warnings"]) std::cerr << "hardsphere: warning: " << w.get<std::string>() << '\n';
    if (spec.json && *spec.json == "-") std::cout << summary.dump(2) << '\n';
    else print_summary(summary, std::cout);
    return 0;
  } catch (const InputError& e) {
    std::cerr << "hardsphere: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hardsphere: internal error: " << e.what() << '\n';
    return 3;
  }
}
