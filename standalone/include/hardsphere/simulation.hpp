#pragma once
//! One complete run as the CLI performs it: initial state, equilibration, timed stepping with
//! dumps, summary. Output files are committed only when the whole run succeeded.
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/init.hpp"
#include "hardsphere/run_summary.hpp"
#include "hardsphere/stepper.hpp"
#include "hardsphere/transport.hpp"

namespace hardsphere {

//! Which engine a run uses.
enum class Engine { Stepper, Event };
Engine parse_engine(const std::string& s);  //!< "stepper" or "event"; throws InputError

//! Transport (RunSpec::transport): lags per correlation window, and the default window in Enskog
//! mean free times: D converges to 1% only past ~75 (the long-time tail; measured at n = 0.5).
constexpr int kTransportLags = 20;
constexpr double kTransportWindowFreeTimes = 100;

//! Most event-engine blocks of a run: one stored value and one advance each.
constexpr int kMaxBlocks = 1000000;

struct RunSpec {
  // Initial state: generated from `init`, or read from a LAMMPS data file.
  InitSpec init;
  std::optional<std::string> read_data;
  std::array<bool, 3> periodic{true, true, true};  //!< boundaries (data files carry none)
  //! Atom types whose spheres are kinematic (ParticleSystem::kinematic): a data file's only.
  std::vector<int> kinematic_types;

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
  int blocks = 20;              //!< block averages for the error bar of Z (event engine), 1..kMaxBlocks

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
  //! Self-diffusion, shear viscosity and thermal conductivity of the measured run (transport.hpp):
  //! correlation window (0: kTransportWindowFreeTimes mean free times) and independent blocks.
  bool transport = false;
  double transport_window = 0;
  int transport_blocks = 10;

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

//! Marks the spheres of `types` kinematic (ParticleSystem::kinematic); refuses a type no sphere
//! has, naming `option` and `source`.
void set_kinematic_types(ParticleSystem& sys, const std::vector<int>& types, const std::string& option,
                         const std::string& source);

//! The initial state a RunSpec describes (generated or read), validated; what read_data skipped
//! of the data file goes to `notes` (the summary's warnings).
ParticleSystem initial_state(const RunSpec& spec, std::vector<std::string>* notes = nullptr);

//! CPU time of this process in seconds (what the seed paper measured).
double process_cpu_seconds();

// The pieces of a run that every adapter reports as the CLI does (the Python module uses them),
// implemented once in the run layer.

//! Refuses (InputError, the CLI's message) a stepper run of `steps` steps from `sys` on `engine`
//! (made with `cfg` and `physics`) that would take more than `work_limit` particle-steps (sub-steps
//! and wall bounces included), or whose wall bounces alone would pass cfg.max_events_per_step.
//! Rough spheres count their rotational energy as the speed collisions can turn it into,
//! sqrt(v^2 + q r^2 w^2); the message names the sphere and its file:line.
void check_stepper_work(const StepperBase& engine, const StepperConfig& cfg, const ParticleSystem& sys,
                        std::int64_t steps, double work_limit, const Physics& physics = {});

//! Refuses (InputError, the CLI's message) an event-engine run of simulated `time` from `sys`
//! whose estimate of events (neighbour-list events for `shell`, wall bounces, gravity; rough
//! spheres' rotation counted as speed, as for the stepper) is more than `work_limit`.
void check_event_work(const ParticleSystem& sys, double shell, double time, double work_limit, const Physics& physics);
//! The same for smooth spheres under `gravity`.
void check_event_work(const ParticleSystem& sys, double shell, double time, double work_limit,
                      const std::array<double, 3>& gravity);

//! Appends the stepper's warnings to j["warnings"]: steps that stopped at cfg.max_events_per_step
//! with contacts unresolved, and overlap detection with steps long enough to miss grazes.
void add_stepper_warnings(nlohmann::json& j, const StepperBase& engine, const StepperConfig& cfg,
                          const ParticleSystem& final_state);

//! The stepper's keys of the run summary (docs/cli.md), its warnings included: steps, dt, grid,
//! detection and precision in use, list rebuilds, sub-steps, and particle-steps per `loop_cpu` second.
void add_stepper_summary(nlohmann::json& j, const StepperBase& engine, const StepperConfig& cfg, Precision precision,
                         const ParticleSystem& final_state, std::int64_t equilibrate_steps, double loop_cpu);

//! The shaped walls' keys (none without them): `shaped_walls`, each wall's words, collisions,
//! resting contacts and work, and `wall_work`, their sum.
void add_shape_summary(nlohmann::json& j, const Physics& physics, const StepCounters& counters);

//! The event engine's keys of the run summary (docs/cli.md) but the block averages
//! (BlockAverages::add_summary): time, grid, shell, event counts and rates per `loop_cpu` second.
void add_event_summary(nlohmann::json& j, const EventEngine& engine, double equilibrate_time, double loop_cpu);

//! Where a measured state came from, as the run summary reports it.
struct SummaryOrigin {
  bool com_removed = false;  //!< the generator removed the centre-of-mass velocity
  std::uint64_t seed = 0;
  int histogram_bins = 40;
};

//! The run summary's keys every engine reports, assembled once for the CLI's run driver and
//! Python's observables(): physics_summary (its overlap tolerance from `rounding_eps`), engine,
//! add_energy_summary and add_rough_summary of the measurement from `initial` to `final_state`
//! (totals.kinetic_energy_initial is that of `initial`), and loop_cpu_seconds. The engine's own
//! keys are added by the caller.
nlohmann::json run_summary(const ParticleSystem& initial, const ParticleSystem& final_state, const RunTotals& totals,
                           const Physics& physics, const SummaryOrigin& origin, const std::string& engine,
                           double rounding_eps, double loop_cpu);

//! The totals of the timed part from an engine's counters, with the initial kinetic energy and
//! momentum of that part.
RunTotals run_totals(const StepCounters& c, double kinetic0, const Vec3d& momentum0);
RunTotals run_totals(const EventCounters& c, double kinetic0, const Vec3d& momentum0);

//! The event engine's block averages (--blocks): Z and the collision rate per block of a
//! measurement, whose standard errors of the mean are the summary's error bars.
class BlockAverages {
 public:
  //! A measurement starting from `start`: its temperature is T in every block's Z.
  explicit BlockAverages(const ParticleSystem& start);
  //! Ends a block `duration` long at the counters `c` (counted since the measurement began).
  void close_block(const EventCounters& c, double duration);
  int blocks() const { return int(z_.size()); }
  //! Sets blocks, compressibility_factor_error and collision_rate_error (0 with fewer than 2 blocks).
  void add_summary(nlohmann::json& j) const;

 private:
  std::size_t n_;
  double temperature_;
  double virial_ = 0;
  std::int64_t collisions_ = 0;
  std::vector<double> z_, rate_;
};

//! The option names a TransportRun's refusals use (the CLI's; Python passes its keywords).
struct TransportNames {
  std::string option = "--transport", window = "--transport-window", blocks = "--transport-blocks";
};

//! Transport coefficients in a run (RunSpec::transport): the tally both engines feed, the samples
//! at whole intervals of the measured run and the blocks of the error bars (transport.hpp). The
//! CLI's run driver and the Python module's run loops use it alike.
class TransportRun {
 public:
  //! Checks the scene and the window against the measured run (InputError, naming the options);
  //! `quantum` is the time the samples must be whole multiples of (the stepper's dt; 0: any).
  TransportRun(const RunSpec& spec, const ParticleSystem& initial, double measured_time, double quantum,
               const TransportNames& names = {});
  //! The measured run starts from `state`: the tally's clock and the first sample.
  void begin(const ParticleSystem& state);
  TransportTally& tally() { return tally_; }
  double interval() const { return interval_; }
  std::int64_t samples() const { return samples_; }  //!< sample intervals in the measured run
  //! Sample `index` (1 .. samples()) of `state`, at index * interval() into the measured run.
  void sample(std::int64_t index, const ParticleSystem& state);
  //! The summary keys (diffusion, ..., transport_temperature).
  void add_summary(nlohmann::json& j) const;

 private:
  TransportTally tally_;
  std::optional<TransportEstimator> estimator_;
  double interval_ = 0;
  std::int64_t samples_ = 0;
  int lags_ = 0, blocks_ = 0;
};

}  // namespace hardsphere
