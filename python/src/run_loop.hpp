#pragma once
//! Simulation::run for Python: the engine runs in chunks with the GIL released; between chunks
//! the GIL is taken back to look for signals (Ctrl-C raises KeyboardInterrupt and leaves the
//! engine at the end of the last chunk, ready to run again), call the user's callback and report
//! progress.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>

#include "simulation.hpp"

namespace hardsphere::python {

//! run(transport=True, transport_window=None, transport_blocks=10): the CLI's --transport options.
struct TransportArgs {
  bool on = false;
  std::optional<double> window;
  std::int64_t blocks = 10;
};

//! `steps` or `time` (steps = round(time / dt), as the CLI's --time), refused over the work
//! limit as the CLI refuses it; `callback(self)` after every `every` steps;
//! `progress(fraction, sim_time)` after each chunk.
void run_stepper(StepperSim& sim, pybind11::object self, std::optional<std::int64_t> steps, std::optional<double> time,
                 pybind11::object callback, std::optional<std::int64_t> every, pybind11::object progress,
                 const TransportArgs& transport = {});

//! `time` of simulated time in `blocks` blocks (the CLI's --blocks, for the error bars);
//! `callback(self)` after every `every` of it.
void run_event(EventSim& sim, pybind11::object self, std::optional<std::int64_t> steps, std::optional<double> time,
               pybind11::object callback, std::optional<double> every, pybind11::object progress, std::int64_t blocks,
               const TransportArgs& transport = {});

}  // namespace hardsphere::python
