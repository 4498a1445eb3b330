#pragma once
//! One complete run as the CLI performs it: initial state, equilibration, timed stepping with
//! dumps, summary. Output files are committed only when the whole run succeeded.
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/stepper.hpp"

namespace hardsphere {

//! Which engine a run uses.
enum class Engine { Stepper, Event };
Engine parse_engine(const std::string& s);  //!< "stepper" or "event"; throws InputError

struct RunSpec {
  // Initial state: generated from `init`, or read from a LAMMPS data file.
  InitSpec init;
  std::optional<std::string> read_data;
  std::array<bool, 3> periodic{true, true, true};  //!< boundaries (data files carry none)

  //! Collision law and gravity, for either engine.
  Physics physics;
  StepperConfig stepper;
  Precision precision = Precision::Double;
  std::int64_t steps = 1000;
  std::int64_t equilibrate = 0;  //!< steps run before measuring (not timed, not counted)

  //! Event engine (exact EDMD): run length and equilibration in simulated time, not steps.
  Engine engine = Engine::Stepper;
  EventConfig event;
  double time = 0;              //!< simulated time measured (event engine)
  double equilibrate_time = 0;  //!< simulated time run first, not measured (event engine)
  int blocks = 20;              //!< block averages for the error bar of Z (event engine)

  //! The most work a run may take before it is refused: particle-steps for the stepper (sub-steps
  //! included), events for the event engine. The default refuses only runs that would take years.
  double work_limit = 1e15;

  std::optional<std::string> write_data, dump, json;
  std::int64_t dump_every = 100;
  //! Tracker: the sphere with this id is written to track_file every track_every (simulated
  //! time; for the stepper a whole number of steps) during the measured run.
  std::optional<std::int64_t> track_id;
  double track_every = 0;
  std::optional<std::string> track_file;
  int histogram_bins = 40;

  //! Called during the measured run (about every 1% for the stepper, after each block for the
  //! event engine) with the fraction done and the simulated time; the CLI's progress line.
  std::function<void(double fraction, double sim_time)> progress;
  //! Called with the summary once the run succeeded and before any output file is committed, e.g.
  //! to print it: if it throws, no output file is left (a summary that cannot be written fails
  //! the run).
  std::function<void(const nlohmann::json& summary)> report;
};

//! Runs the job with spec.engine and returns the JSON summary (keys documented in docs/cli.md).
//! Throws InputError.
nlohmann::json run_simulation(const RunSpec& spec);

//! Refuses (InputError) output paths that collide or cannot be written (see check_output_paths).
void check_outputs(const RunSpec& spec);

//! The initial state a RunSpec describes (generated or read), validated.
ParticleSystem initial_state(const RunSpec& spec);

//! CPU time of this process in seconds (what the seed paper measured).
double process_cpu_seconds();

}  // namespace hardsphere
