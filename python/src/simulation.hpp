#pragma once
//! The engines as the Python module holds them: a shared snapshot of the current state (the
//! arrays Python sees), the observables as the CLI's JSON summary reports them, and the CLI's
//! outputs. Plain C++ over the public headers; the Python glue is in module.cpp and run_loop.cpp.
#include <sys/types.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "hardsphere/event_engine.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"
#include "hardsphere/run_summary.hpp"
#include "hardsphere/simulation.hpp"
#include "hardsphere/stepper.hpp"

namespace hardsphere::python {

//! A state with what the CLI's summary needs to know of its origin.
struct SystemData {
  ParticleSystem sys;
  std::uint64_t seed = 1;    //!< the seed it was generated with (1, the CLI's default, otherwise)
  bool com_removed = false;  //!< generated (momentum zeroed), not read or given
  double rounding_eps = 0;   //!< overlaps accepted when read (an engine's rounding)
};

//! A call that would change an engine from inside its own run() (a callback): RuntimeError.
struct ReentryError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

//! What both engines share: the measurement since construction or reset_counters().
class Simulation {
 public:
  Simulation(const SystemData& start, const Physics& physics) : physics_(physics), origin_(start) {}
  virtual ~Simulation() = default;
  virtual const char* name() const = 0;
  //! The Python class ("Stepper", "EventEngine"), for messages.
  virtual const char* class_name() const = 0;
  //! The current state in id order; shared, so arrays handed out stay valid after later runs.
  std::shared_ptr<const ParticleSystem> state() const;
  //! The CLI's JSON summary of the measurement so far.
  nlohmann::json observables(std::int64_t histogram_bins) const;
  void reset_counters();
  //! The CLI's --write-data and a one-frame --dump of the current state, as atomic files.
  void write_data(const std::string& path) const;
  void write_dump(const std::string& path) const;
  //! One frame of the current state, timestep the steps or events so far (as the CLI's frames).
  void write_frame(DumpWriter& dump) const { dump.write_frame(dump_timestep(), *state()); }
  double loop_cpu_seconds() const { return cpu_; }
  void add_cpu(double seconds) { cpu_ += seconds; }
  virtual double sim_time() const = 0;
  //! The engine feeds `tally` from now on (nullptr: none): run(transport=True).
  virtual void set_transport(TransportTally* tally) = 0;
  //! The transport keys of the last complete run(transport=True), added to observables().
  void set_transport_keys(nlohmann::json keys) { transport_keys_ = std::move(keys); }
  const SystemData& origin() const { return origin_; }
  const Physics& physics() const { return physics_; }
  //! Gravity from the next step or time on (the engine's set_gravity: InputError naming the
  //! value). The summary's potential
  //! energies are then those of the new gravity at both ends (gravity_changed in it).
  void set_gravity(const std::array<double, 3>& g);
  //! Refuses (InputError) to touch an engine that another thread is running (its GIL is released).
  void check_idle() const;
  //! A run() in progress, from its checks to its return, callbacks and progress reports included.
  //! Refuses a run() (or another call that changes the engine, `method`) that would start inside
  //! it: from its own callback with ReentryError (the loop would lose its place: steps, blocks,
  //! callback times), from another thread with check_idle's InputError.
  class InRun {
   public:
    explicit InRun(Simulation& s) : s_(s) { s_.check_not_in_run("run"), s_.run_thread_ = std::this_thread::get_id(); }
    ~InRun() { s_.run_thread_.reset(); }
    InRun(const InRun&) = delete;
    InRun& operator=(const InRun&) = delete;

   private:
    Simulation& s_;
  };
  void check_not_in_run(const char* method) const;
  //! Marks the engine as running (a chunk with the GIL released) for the lifetime of the object.
  class Running {
   public:
    explicit Running(Simulation& s) : s_(s) { s_.check_idle(), s_.running_ = true; }
    ~Running() { s_.running_ = false; }
    Running(const Running&) = delete;
    Running& operator=(const Running&) = delete;

   private:
    Simulation& s_;
  };

 protected:
  void changed() { snapshot_.reset(); }
  //! The reference for energy and momentum changes: the state now.
  void start_measurement();
  virtual ParticleSystem engine_state() const = 0;
  virtual void engine_reset() = 0;
  virtual RunTotals totals() const = 0;
  virtual double rounding_epsilon() const = 0;
  virtual void add_summary(nlohmann::json& j) const = 0;
  virtual std::string title() const = 0;
  virtual std::int64_t dump_timestep() const = 0;
  virtual void engine_set_gravity(const std::array<double, 3>& g) = 0;
  virtual std::array<double, 3> engine_gravity() const = 0;

  Physics physics_;
  bool gravity_changed_ = false;   // set_gravity() during the measurement
  nlohmann::json transport_keys_;  // set_transport_keys()
  SystemData origin_;

 private:
  mutable std::shared_ptr<const ParticleSystem> snapshot_;
  std::atomic<bool> running_{false};
  std::optional<std::thread::id> run_thread_;  // the thread in run(), set and read with the GIL held
  double kinetic0_ = 0;
  std::shared_ptr<const ParticleSystem> start_;  // the state at the start of the measurement
  Vec3d momentum0_;
  double cpu_ = 0;
};

class StepperSim final : public Simulation {
 public:
  StepperSim(const SystemData& start, const Physics& physics, const StepperConfig& cfg, Precision precision);
  const char* name() const override { return "stepper"; }
  const char* class_name() const override { return "Stepper"; }
  void run(std::int64_t steps);
  //! Refuses (InputError, the CLI's message) `steps` more steps over the work limit.
  void check_work(std::int64_t steps) const;
  double dt() const { return cfg_.dt; }
  std::int64_t steps() const { return engine().counters().steps; }
  double sim_time() const override { return engine().counters().sim_time; }
  const StepperBase& engine() const { return check_idle(), *engine_; }
  void set_transport(TransportTally* tally) override { engine_->set_transport(tally); }

 private:
  ParticleSystem engine_state() const override { return engine_->state(); }
  void engine_reset() override { engine_->reset_counters(); }
  RunTotals totals() const override;
  double rounding_epsilon() const override;
  void add_summary(nlohmann::json& j) const override;
  std::string title() const override;
  std::int64_t dump_timestep() const override { return steps(); }
  void engine_set_gravity(const std::array<double, 3>& g) override { engine_->set_gravity(g); }
  std::array<double, 3> engine_gravity() const override { return engine_->gravity(); }

  StepperConfig cfg_;
  Precision precision_;
  std::unique_ptr<StepperBase> engine_;
};

class EventSim final : public Simulation {
 public:
  EventSim(const SystemData& start, const Physics& physics, const EventConfig& cfg);
  const char* name() const override { return "event"; }
  const char* class_name() const override { return "EventEngine"; }
  //! Runs to the absolute time `t_end` (since construction), part of a run ending at `run_end`.
  void run_until(double t_end, double run_end);
  //! Refuses (InputError, the CLI's message) a run of `duration` over the work limit.
  void check_work(double duration) const;
  //! Ends a block of the measurement (the CLI's --blocks) `duration` long at the current counters.
  void close_block(double duration) { blocks_->close_block(engine_->counters(), duration); }
  double time() const { return engine().time(); }
  std::int64_t events() const { return engine().counters().events; }
  double sim_time() const override { return engine().counters().sim_time; }
  void set_transport(TransportTally* tally) override { engine_->set_transport(tally); }
  const EventEngine& engine() const { return check_idle(), *engine_; }

 private:
  ParticleSystem engine_state() const override { return engine_->state(); }
  void engine_reset() override {
    engine_->reset_counters();
    blocks_.emplace(engine_->state());
  }
  RunTotals totals() const override;
  double rounding_epsilon() const override;
  void add_summary(nlohmann::json& j) const override;
  std::string title() const override;
  std::int64_t dump_timestep() const override { return events(); }
  void engine_set_gravity(const std::array<double, 3>& g) override { engine_->set_gravity(g); }
  std::array<double, 3> engine_gravity() const override { return engine_->gravity(); }

  EventConfig cfg_;
  std::unique_ptr<EventEngine> engine_;
  std::optional<BlockAverages> blocks_;  // of the measurement since construction or reset_counters()
};

//! hs.DumpWriter: the CLI's --dump, a frame per write(), the file committed by close() (until
//! then it is a temporary, removed if the writer is discarded or the process dies, by a signal
//! too). It belongs to the process that opened it: a forked child may not write or close it.
class DumpFile {
 public:
  explicit DumpFile(const std::string& path);
  void write(const Simulation& sim);
  void close();
  //! Refuses (InputError) a closed writer and one a forked child inherited.
  void check_usable() const;
  void discard() { dump_.reset(); }
  bool closed() const { return !dump_; }
  std::int64_t frames() const { return frames_; }
  const std::string& path() const { return path_; }

 private:
  DumpWriter& open();
  std::string path_;
  pid_t owner_;
  std::optional<DumpWriter> dump_;
  std::int64_t frames_ = 0;
};

}  // namespace hardsphere::python
