// The engines behind the Python module, measured and summarised as the run driver does it
// (standalone/src/run), so a Python run reports what the CLI reports for the same run.
#include "simulation.hpp"

#include <unistd.h>

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "hardsphere/atomic_file.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/precision.hpp"

namespace hardsphere::python {

namespace {
constexpr std::int64_t kMaxBins = 1000000;  // the CLI's --histogram-bins bound (cli/options.cpp)
}  // namespace

void Simulation::check_idle() const {
  if (running_) throw InputError("the engine is running in another thread; wait for its run() to return");
}

void Simulation::check_not_in_run(const char* method) const {
  check_idle();
  if (!run_thread_) return;
  if (*run_thread_ != std::this_thread::get_id())
    throw InputError("the engine is running in another thread; wait for its run() to return");
  const std::string call = std::string(class_name()) + "." + method + "()";
  throw ReentryError(call + " called from inside this " + class_name() +
                     "'s own run() (its callback or progress function): the run in progress would lose its place; " +
                     "return from the callback (returning False stops the run) and call " + call +
                     " after run() returns");
}

std::shared_ptr<const ParticleSystem> Simulation::state() const {
  check_idle();
  if (!snapshot_) snapshot_ = std::make_shared<const ParticleSystem>(engine_state());
  return snapshot_;
}

void Simulation::start_measurement() {
  const auto s = state();
  kinetic0_ = kinetic_energy(*s);
  momentum0_ = total_momentum(*s);
  start_ = s;
  cpu_ = 0;
  gravity_changed_ = false;
}

void Simulation::reset_counters() {
  check_not_in_run("reset_counters");
  engine_reset();
  start_measurement();
  transport_keys_ = nullptr;
}

nlohmann::json Simulation::observables(std::int64_t histogram_bins) const {
  if (histogram_bins < 1) throw InputError("histogram_bins " + std::to_string(histogram_bins) + " must be >= 1");
  if (histogram_bins > kMaxBins)
    throw InputError("histogram_bins " + std::to_string(histogram_bins) + " is more than " + std::to_string(kMaxBins));
  const ParticleSystem& fin = *state();
  RunTotals t = totals();
  t.kinetic_energy_initial = kinetic0_;
  t.momentum_initial = momentum0_;
  nlohmann::json j = run_summary(*start_, fin, t, physics_, {origin_.com_removed, origin_.seed, int(histogram_bins)},
                                 name(), rounding_epsilon(), cpu_);
  add_summary(j);
  // Potential energies are the current gravity's at both ends (docs/python.md).
  if (gravity_changed_) j["gravity_changed"] = true;
  if (transport_keys_.is_object()) j.update(transport_keys_);
  return j;
}

void Simulation::set_gravity(const std::array<double, 3>& g) {
  check_not_in_run("gravity");
  check_idle();
  engine_set_gravity(g);
  physics_.gravity = engine_gravity();
  gravity_changed_ = true;
}

void Simulation::write_data(const std::string& path) const {
  check_output_paths({{"write_data", path}});
  install_cleanup_signal_handlers();
  hardsphere::write_data(path, *state(), title());
}

void Simulation::write_dump(const std::string& path) const {
  check_output_paths({{"write_dump", path}});
  install_cleanup_signal_handlers();
  DumpWriter dump(path, physics_.rough());
  dump.write_frame(dump_timestep(), *state());
  dump.commit();
}

DumpFile::DumpFile(const std::string& path) : path_(path), owner_(::getpid()) {
  check_output_paths({{"DumpWriter", path}});
  // Before the temporary exists: a terminating signal removes it from then on (signals Python
  // or the user handle keep their handlers; the process then ends by unwinding, which discards).
  install_cleanup_signal_handlers();
  dump_.emplace(path);
}

void DumpFile::check_usable() const {
  if (!dump_) throw InputError("DumpWriter '" + path_ + "' is closed");
  if (owner_ != ::getpid())
    throw InputError("DumpWriter '" + path_ + "' was opened by process " + std::to_string(owner_) +
                     "; a forked process cannot write or close it");
}

DumpWriter& DumpFile::open() {
  check_usable();
  return *dump_;
}

void DumpFile::write(const Simulation& sim) {
  if (frames_ == 0) open().set_omega(sim.physics().rough());  // the first engine's columns for every frame
  sim.write_frame(open());
  // Nothing stays buffered between frames: a forked child's copy of the buffer, flushed at its
  // exit, would write part of a frame into the parent's file again.
  auto& out = open().file().stream();
  out.flush();
  if (!out) throw InputError("error while writing '" + path_ + "'");
  ++frames_;
}

void DumpFile::close() {
  if (!dump_) return;
  check_usable();  // a forked child's copy
  // Committed or not, the writer is done: a failed commit leaves no file and no open temporary.
  struct Done {
    std::optional<DumpWriter>& d;
    ~Done() { d.reset(); }
  } done{dump_};
  dump_->commit();
}

// ---- stepper

StepperSim::StepperSim(const SystemData& start, const Physics& physics, const StepperConfig& cfg, Precision precision)
    : Simulation(start, physics), cfg_(cfg), precision_(precision) {
  engine_ = make_stepper(start.sys, physics_, cfg_, precision_);
  start_measurement();
}

void StepperSim::check_work(std::int64_t steps) const {
  check_stepper_work(engine(), cfg_, *state(), steps, cfg_.max_particle_steps, physics_);
}

void StepperSim::run(std::int64_t steps) {
  changed();
  engine_->run(steps);
}

RunTotals StepperSim::totals() const { return run_totals(engine_->counters(), 0, {}); }

double StepperSim::rounding_epsilon() const { return hardsphere::rounding_epsilon(precision_); }

std::string StepperSim::title() const { return "hardsphere state after " + std::to_string(steps()) + " steps"; }

// The stepper's keys of the CLI's summary (one implementation: hardsphere/simulation.hpp).
void StepperSim::add_summary(nlohmann::json& j) const {
  add_stepper_summary(j, *engine_, cfg_, precision_, *state(), 0, loop_cpu_seconds());
  add_shape_summary(j, physics_, engine_->counters());
}

// ---- event engine

EventSim::EventSim(const SystemData& start, const Physics& physics, const EventConfig& cfg)
    : Simulation(start, physics), cfg_(cfg) {
  engine_ = std::make_unique<EventEngine>(start.sys, physics_, cfg);
  blocks_.emplace(engine_->state());
  start_measurement();
}

void EventSim::run_until(double t_end, double run_end) {
  changed();
  // t_end - time() + time() is t_end exactly when the chunk starts past half of it (run_loop.cpp).
  engine_->advance(std::max(0.0, t_end - engine_->time()), run_end);
}

void EventSim::check_work(double duration) const {
  check_event_work(*state(), engine().shell(), duration, cfg_.max_events, physics_);
}

RunTotals EventSim::totals() const { return run_totals(engine_->counters(), 0, {}); }

// The event engine computes in double whatever the stepper's precision.
double EventSim::rounding_epsilon() const { return hardsphere::rounding_epsilon(Precision::Double); }

std::string EventSim::title() const {
  return "hardsphere state after event-driven time " + std::to_string(engine_->counters().sim_time);
}

// The event engine's keys of the CLI's summary (one implementation: hardsphere/simulation.hpp).
void EventSim::add_summary(nlohmann::json& j) const {
  add_event_summary(j, *engine_, 0.0, loop_cpu_seconds());
  blocks_->add_summary(j);
}

}  // namespace hardsphere::python
