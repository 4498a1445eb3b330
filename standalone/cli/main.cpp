// hardsphere: command-line front end. It only parses options and calls the library.
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <new>
#include <sstream>
#include <string>

#include "hardsphere/atomic_file.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/simulation.hpp"
#include "options.hpp"

using namespace hardsphere;

namespace {

// Elastic runs show how well energy was kept; inelastic ones what the collisions dissipated.
std::string energy_line(const nlohmann::json& j) {
  std::ostringstream o;
  if (j["restitution"].get<double>() < 1.0)
    o << "  dissipated energy " << j["dissipated_energy"].get<double>() << " (restitution "
      << j["restitution"].get<double>() << ")\n";
  else
    o << "  energy drift      " << j["energy_rel_drift"].get<double>() << " (relative)\n";
  return o.str();
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
    << energy_line(j) << "  max overlap       " << j["max_overlap"].get<double>() << "\n"
    << "  speed KS distance " << j["speed_ks_distance"].get<double>() << " from Maxwell-Boltzmann\n"
    << "  CPU time (loop)   " << j["loop_cpu_seconds"].get<double>() << " s, "
    << j["collisions_per_second"].get<double>() << " collisions/s, " << j["events_per_second"].get<double>()
    << " events/s\n";
}

void print_summary(const nlohmann::json& j, std::ostream& o) {
  if (j.value("engine", "stepper") == "event") return print_event_summary(j, o);
  o << "hardsphere: " << j["n"] << " spheres, packing fraction " << j["packing_fraction"].get<double>() << ", "
    << j["steps"] << " steps of dt " << j["dt"].get<double>() << " (" << j["scene_kernel"].get<std::string>()
    << ", cells " << j["cells_per_dim"].dump() << ")\n"
    << "  collisions        " << j["collisions"] << " (" << j["collision_rate_per_particle"].get<double>()
    << " per particle per unit time)\n"
    << "  temperature       " << j["temperature"].get<double>() << "\n"
    << "  Z = PV/NkT        " << j["compressibility_factor"].get<double>() << "\n"
    << energy_line(j) << "  max overlap       " << j["max_overlap"].get<double>() << "\n"
    << "  speed KS distance " << j["speed_ks_distance"].get<double>() << " from Maxwell-Boltzmann\n"
    << "  CPU time (loop)   " << j["loop_cpu_seconds"].get<double>() << " s, "
    << j["particle_steps_per_second"].get<double>() << " particle-steps/s\n";
}

// Describes the run a std::bad_alloc interrupted, so the refusal names what was too large.
std::string run_size(const RunSpec& spec) {
  if (spec.read_data) return "the spheres of '" + *spec.read_data + "'";
  return std::to_string(spec.init.n) + " spheres (--n " + std::to_string(spec.init.n) + ")";
}

// A progress line on a terminal's stderr for runs longer than a couple of seconds: percent,
// simulated time and the time left at the rate so far; erased when the run ends.
class ProgressLine {
 public:
  void operator()(double fraction, double sim_time) {
    const auto now = Clock::now();
    if (!first_) {  // the rate is measured from the first report, after set-up
      first_ = true, t0_ = now, f0_ = fraction;
      return;
    }
    if (fraction >= 1.0) {
      if (shown_) std::cerr << '\r' << std::string(72, ' ') << '\r' << std::flush;
      return;
    }
    if (seconds(start_, now) < 2.0 || fraction <= f0_) return;
    const double left = seconds(t0_, now) / (fraction - f0_) * (1 - fraction);
    std::cerr << "\rhardsphere: " << int(100 * fraction) << "% done, simulated time " << sim_time << ", about "
              << int(left + 0.5) << " s left   " << std::flush;
    shown_ = true;
  }

 private:
  using Clock = std::chrono::steady_clock;
  static double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
  }
  Clock::time_point start_ = Clock::now(), t0_;
  double f0_ = 0;
  bool first_ = false, shown_ = false;
};

// A standard stream started closed must stay so: the first file opened would otherwise take its
// descriptor, and the summary would be written into an output file. Standard output is held by a
// read-only descriptor, so writing the summary fails as it would have.
void hold_closed_standard_streams() {
  for (const int fd : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) {
    if (fcntl(fd, F_GETFD) != -1) continue;
    const int held = open("/dev/null", fd == STDERR_FILENO ? O_WRONLY : O_RDONLY);
    if (held >= 0 && held != fd) {
      dup2(held, fd);
      close(held);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  hold_closed_standard_streams();
  cli::CommandLine cmd;
  try {
    cmd = cli::parse_command_line(argc, argv);
    if (cmd.help) {
      std::cout << cmd.help_text;
      return 0;
    }
    // From here on a signal removes the temporaries of the outputs before the process dies.
    install_cleanup_signal_handlers();
    // A scene that runs but cannot settle (a chute without wall friction) is said before the run.
    const std::string flow = unbounded_flow(cmd.spec.physics, cmd.spec.periodic, cmd.spec.stepper.names);
    if (!flow.empty()) std::cerr << "hardsphere: warning: " << flow << '\n';
    if (!cmd.quiet && isatty(STDERR_FILENO)) cmd.spec.progress = ProgressLine();
    // The summary goes out before the output files are committed: if standard output fails, the
    // run fails and leaves no file.
    cmd.spec.report = [&](const nlohmann::json& summary) {
      for (const auto& w : summary["warnings"]) std::cerr << "hardsphere: warning: " << w.get<std::string>() << '\n';
      if (cmd.spec.json && *cmd.spec.json == "-")
        std::cout << summary.dump(2) << '\n';
      else
        print_summary(summary, std::cout);
      std::cout.flush();
      if (!std::cout) throw InputError("cannot write the summary to standard output");
    };
    run_simulation(cmd.spec);
    return 0;
  } catch (const InputError& e) {
    std::cerr << "hardsphere: error: " << e.what() << '\n';
    return 2;
  } catch (const std::bad_alloc&) {
    // A run too large for this machine is refused like any other impossible request.
    std::cerr << "hardsphere: error: not enough memory for " << run_size(cmd.spec) << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "hardsphere: internal error: " << e.what() << '\n';
    return 3;
  } catch (...) {
    std::cerr << "hardsphere: internal error: unknown exception\n";
    return 3;
  }
}
