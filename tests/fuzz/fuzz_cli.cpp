// Fuzz target: the command line. The input is split into arguments at NUL bytes and newlines and
// parsed exactly as `hardsphere` parses argv. A refusal (InputError) is expected for most inputs.
// An accepted run is shrunk so it stays fast (at most 64 spheres, 50 steps or a short simulated
// time, a work limit) with every output path cleared, run, and its JSON summary checked: numbers
// finite, energy conserved, a warning whenever spheres overlap beyond rounding. Anything else
// aborts: a finding.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_check.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/simulation.hpp"
#include "options.hpp"

using namespace hardsphere;
using hardsphere::fuzz::require;

namespace {

constexpr std::size_t kMaxArgs = 64;

std::vector<std::string> split_args(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> args{"hardsphere"};
  std::string cur;
  for (std::size_t i = 0; i < size && args.size() < kMaxArgs; ++i) {
    const char c = char(data[i]);
    if (c == '\0' || c == '\n') {
      args.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(c);
    }
  }
  if (!cur.empty() && args.size() < kMaxArgs) args.push_back(cur);
  return args;
}

//! The run the fuzzer may afford: small, short, writing nothing.
void shrink(RunSpec& spec) {
  spec.init.n = std::min<std::int64_t>(spec.init.n, 64);
  spec.steps = std::min<std::int64_t>(spec.steps, 50);
  spec.equilibrate = std::min<std::int64_t>(spec.equilibrate, 50);
  spec.time = std::min(spec.time, 1.0);
  spec.equilibrate_time = std::min(spec.equilibrate_time, 1.0);
  spec.blocks = std::min(spec.blocks, 20);
  spec.histogram_bins = std::min(spec.histogram_bins, 1000);
  spec.work_limit = 1e6;
  spec.write_data.reset();
  spec.dump.reset();
  spec.json.reset();
}

double number(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number()) fuzz::fail(std::string("summary key '") + key + "' missing or not a number");
  return it->get<double>();
}

void finite(const nlohmann::json& j, const char* key) {
  if (!std::isfinite(number(j, key)))
    fuzz::fail(std::string("summary key '") + key + "' is not finite: " + j[key].dump());
}

void finite_array(const nlohmann::json& a, const char* key) {
  if (!a.is_array()) fuzz::fail(std::string("summary key '") + key + "' is not an array");
  for (const auto& x : a)
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      fuzz::fail(std::string("summary key '") + key + "' has a non-finite entry: " + a.dump());
}

void check_summary(const nlohmann::json& j, const RunSpec& spec) {
  for (const char* key : {"n", "packing_fraction", "collisions", "wall_collisions", "collision_rate_per_particle",
                          "kinetic_energy_initial", "kinetic_energy_final", "energy_rel_drift", "temperature",
                          "pair_virial", "compressibility_factor", "pressure", "max_overlap", "overlap_tolerance",
                          "speed_ks_distance", "sim_time", "loop_cpu_seconds"})
    finite(j, key);
  finite_array(j["box"]["lo"], "box.lo");
  finite_array(j["box"]["hi"], "box.hi");
  finite_array(j["momentum_initial"], "momentum_initial");
  finite_array(j["momentum_final"], "momentum_final");
  finite(j["speed_histogram"], "lo");
  finite(j["speed_histogram"], "hi");
  if (spec.engine == Engine::Event) {
    finite(j, "compressibility_factor_error");
    finite(j, "collision_rate_error");
  } else {
    finite(j, "dt");
    require(j["steps"].get<std::int64_t>() == spec.steps, "stepper ran the steps asked for");
  }
  const auto& wall_p = j["wall_pressure"];
  for (int d = 0; d < 3; ++d) {
    const bool expect_null = j["box"]["boundary"].get<std::string>()[2 * d] == 'p' || !(number(j, "sim_time") > 0);
    if (expect_null != wall_p[d].is_null())
      fuzz::fail("wall_pressure " + wall_p.dump() + " null where it should not be");
    if (!expect_null && !std::isfinite(wall_p[d].get<double>()))
      fuzz::fail("wall_pressure not finite: " + wall_p.dump());
  }
  if (!spec.read_data) require(number(j, "n") == double(spec.init.n), "n spheres generated");
  const double tol = spec.precision == Precision::Float ? 1e-4 : 1e-9;
  if (!(std::abs(number(j, "energy_rel_drift")) <= tol))
    fuzz::fail("energy_rel_drift " + j["energy_rel_drift"].dump() + " beyond " + std::to_string(tol));
  if (number(j, "max_overlap") > number(j, "overlap_tolerance") && j["warnings"].empty())
    fuzz::fail("max_overlap " + j["max_overlap"].dump() + " > overlap_tolerance " + j["overlap_tolerance"].dump() +
               " without a warning");
  (void)j.dump();  // serialisable (no invalid UTF-8 in strings)
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<std::string> args = split_args(data, size);
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  cli::CommandLine cmd;
  try {
    cmd = cli::parse_command_line(int(argv.size()), argv.data());
  } catch (const InputError&) {
    return 0;  // refused: the expected outcome for most inputs
  } catch (const std::exception& e) {
    fuzz::fail(std::string("parse_command_line threw a non-InputError: ") + e.what());
  }
  // The data-file target covers files; a fuzzer-made path might name /dev/zero or a FIFO.
  if (cmd.help || cmd.spec.read_data) return 0;
  RunSpec spec = cmd.spec;
  shrink(spec);
  nlohmann::json summary;
  try {
    summary = run_simulation(spec);
  } catch (const InputError&) {
    return 0;
  } catch (const std::exception& e) {
    fuzz::fail(std::string("run_simulation threw a non-InputError: ") + e.what());
  }
  check_summary(summary, spec);
  return 0;
}
