#pragma once
//! One engine as the run driver (run_driver.cpp) uses it. Each adapter checks the run length it
//! is given, runs its own measured loop (steps for the stepper, simulated time for the event
//! engine) and adds the summary keys of its own; everything else is the driver's.
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "hardsphere/lammps_io.hpp"
#include "hardsphere/particles.hpp"
#include "hardsphere/run_summary.hpp"
#include "hardsphere/simulation.hpp"
#include "io/tracker.hpp"

namespace hardsphere {

//! What the measured loop writes into as it goes.
struct RunOutputs {
  DumpWriter* dump = nullptr;
  Tracker* tracker = nullptr;
  const std::function<void(double fraction, double sim_time)>* progress = nullptr;
  TransportRun* transport = nullptr;  //!< fed and sampled, begun by measure()
};

class EngineRun {
 public:
  virtual ~EngineRun() = default;
  //! Builds the engine for the initial state and refuses (InputError) a run over the work limit.
  virtual void start(const ParticleSystem& sys) = 0;
  virtual const char* name() const = 0;  //!< the summary's "engine" and the tracker's header
  //! The measured run's length in simulated time.
  virtual double measured_time() const = 0;
  //! The time samples must be whole multiples of (the stepper's dt; 0: any time).
  virtual double time_quantum() const = 0;
  //! Refuses (InputError) a tracker interval the engine cannot sample at.
  virtual void check_track_every(double every) const = 0;
  //! The state in id order (the order sphere() and the tracker index).
  virtual ParticleSystem state() const = 0;
  //! Runs the unmeasured part; false if there is none.
  virtual bool equilibrate() = 0;
  virtual void reset_counters() = 0;
  //! The measured run; returns its CPU seconds.
  virtual double measure(const RunOutputs& out) = 0;
  virtual RunTotals totals(double kinetic0, const Vec3d& momentum0) const = 0;
  //! Machine epsilon of the engine's arithmetic (the overlap its rounding can leave).
  virtual double rounding_epsilon() const = 0;
  virtual void add_summary(nlohmann::json& j, const ParticleSystem& final_state, double cpu) const = 0;
  virtual std::string final_title() const = 0;  //!< the final data file's title line
};

//! Check the spec's run length for their engine (InputError) before any state is made.
std::unique_ptr<EngineRun> make_stepper_run(const RunSpec& spec);
std::unique_ptr<EngineRun> make_event_run(const RunSpec& spec);

}  // namespace hardsphere
