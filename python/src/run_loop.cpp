// Chunks are short enough for Ctrl-C to answer at once and long enough that the GIL round trip
// costs nothing measurable (bench/python_overhead.py); they change no result (each engine carries
// its whole state across calls).
#include "run_loop.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/simulation.hpp"

namespace py = pybind11;

namespace hardsphere::python {

namespace {

//! Work per chunk: particle-steps for the stepper, events for the event engine.
constexpr double kChunkWork = 1e6;
//! The most callbacks of an event-engine run (the stepper's are bounded by its steps).
constexpr double kMaxCallbacks = 1e15;

//! Measures CPU time of the loop without the user's callbacks.
class LoopClock {
 public:
  explicit LoopClock(Simulation& sim) : sim_(sim), t0_(process_cpu_seconds()) {}
  ~LoopClock() { sim_.add_cpu(process_cpu_seconds() - t0_ - outside_); }
  template <class F>
  auto outside(F&& f) {
    const double t = process_cpu_seconds();
    struct Back {
      LoopClock& c;
      double t;
      ~Back() { c.outside_ += process_cpu_seconds() - t; }
    } back{*this, t};
    return f();
  }

 private:
  Simulation& sim_;
  double t0_, outside_ = 0;
};

void check_signals() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

//! The user's callback; returning False stops the run.
bool call_back(LoopClock& clock, const py::object& callback, const py::object& self) {
  if (callback.is_none()) return true;
  const py::object r = clock.outside([&] { return callback(self); });
  return !(py::isinstance<py::bool_>(r) && !r.cast<bool>());
}

void report(LoopClock& clock, const py::object& progress, double fraction, double sim_time) {
  if (!progress.is_none()) clock.outside([&] { return progress(fraction, sim_time); });
}

std::string number(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}

//! run(transport=True): the CLI's TransportRun over this run, fed by the engine while it lasts;
//! its keys reach observables() only when the whole run was done (any run clears the last ones).
class TransportSampling {
 public:
  TransportSampling(Simulation& sim, const TransportArgs& a, double measured_time, double quantum) : sim_(sim) {
    sim.set_transport_keys(nullptr);
    if (!a.on) {
      if (a.window || a.blocks != 10) throw InputError("transport_window and transport_blocks need transport=True");
      return;
    }
    if (a.window && !(*a.window > 0 && std::isfinite(*a.window)))
      throw InputError("transport_window " + number(*a.window) + " must be positive and finite");
    if (a.blocks < 2 || a.blocks > 100000)
      throw InputError("transport_blocks " + std::to_string(a.blocks) + " must be 2 to 100000");
    RunSpec spec;
    spec.physics = sim.physics();
    spec.transport = true;
    spec.transport_window = a.window.value_or(0.0);
    spec.transport_blocks = int(a.blocks);
    run_.emplace(spec, *sim.state(), measured_time, quantum,
                 TransportNames{"transport=True", "transport_window", "transport_blocks"});
    run_->begin(*sim.state());
    sim.set_transport(&run_->tally());
  }
  ~TransportSampling() {
    if (run_) sim_.set_transport(nullptr);
  }
  TransportSampling(const TransportSampling&) = delete;
  TransportSampling& operator=(const TransportSampling&) = delete;
  bool on() const { return run_.has_value(); }
  double interval() const { return run_->interval(); }
  std::int64_t samples() const { return run_->samples(); }
  void sample(std::int64_t k) { run_->sample(k, *sim_.state()); }
  void finish() {
    nlohmann::json j;
    run_->add_summary(j);
    sim_.set_transport_keys(std::move(j));
  }

 private:
  Simulation& sim_;
  std::optional<TransportRun> run_;
};

}  // namespace

void run_stepper(StepperSim& sim, py::object self, std::optional<std::int64_t> steps, std::optional<double> time,
                 py::object callback, std::optional<std::int64_t> every, py::object progress,
                 const TransportArgs& transport_args) {
  const Simulation::InRun in_run(sim);
  if (steps && time) throw InputError("steps and time both set the run length; give one");
  if (!steps && !time) throw InputError("run needs steps=N or time=T");
  const double dt = sim.dt();
  if (time) {
    if (!(*time >= 0) || !std::isfinite(*time)) throw InputError("time " + number(*time) + " must be >= 0");
    if (*time / dt > 1e15) throw InputError("time " + number(*time) + " / dt is more than 1e15 steps");
    steps = std::llround(*time / dt);
  }
  if (*steps < 0) throw InputError("steps = " + std::to_string(*steps) + " must be >= 0");
  if (every && *every < 1) throw InputError("every = " + std::to_string(*every) + " must be >= 1 (steps)");
  if (!callback.is_none() && !every) throw InputError("callback needs every=K (steps between calls)");
  if (callback.is_none() && every)
    throw InputError("every = " + std::to_string(*every) + " needs a callback (it says when to call it)");
  const std::int64_t total = *steps;
  sim.check_work(total);
  TransportSampling transport(sim, transport_args, double(total) * dt, dt);
  // Transport samples every `every_t` steps (the interval is a whole number of steps).
  const std::int64_t every_t = transport.on() ? std::llround(transport.interval() / dt) : total;
  std::int64_t next_t = transport.on() ? std::min(every_t, total) : total;
  const double n = double(std::max<std::size_t>(sim.state()->size(), 1));
  const std::int64_t chunk = std::max<std::int64_t>(1, std::int64_t(kChunkWork / n));
  LoopClock clock(sim);
  std::int64_t done = 0, next_call = every ? std::min(*every, total) : total;
  while (done < total) {
    const std::int64_t k = std::min({chunk, total - done, next_call - done, next_t - done});
    {
      Simulation::Running running(sim);
      py::gil_scoped_release release;
      sim.run(k);
    }
    done += k;
    if (transport.on() && done == next_t) {
      if (done / every_t <= transport.samples()) transport.sample(done / every_t);
      next_t = std::min(next_t + every_t, total);
    }
    check_signals();
    if (every && done == next_call) {
      next_call = std::min(next_call + *every, total);
      if (done % *every == 0 && !call_back(clock, callback, self)) break;
    }
    report(clock, progress, double(done) / double(total), sim.sim_time());
  }
  if (transport.on() && done == total) transport.finish();
}

namespace {

//! The event engine's run arguments, refused as the CLI refuses them (before anything runs).
void check_event_run(EventSim& sim, std::optional<std::int64_t> steps, std::optional<double> time,
                     const py::object& callback, std::optional<double> every, std::int64_t blocks) {
  if (steps) throw InputError("steps is a stepper option; the event engine runs for time (simulated time)");
  if (!time) throw InputError("the event engine needs time=T (simulated time to run)");
  if (!(*time > 0) || !std::isfinite(*time))
    throw InputError("time = " + number(*time) +
                     " must be positive and finite (event engine runs for a simulated time)");
  if (every && (!(*every > 0) || !std::isfinite(*every)))
    throw InputError("every = " + number(*every) + " must be positive and finite (simulated time)");
  if (!callback.is_none() && !every) throw InputError("callback needs every=T (simulated time between calls)");
  if (callback.is_none() && every)
    throw InputError("every = " + number(*every) + " needs a callback (it says when to call it)");
  if (blocks < 1) throw InputError("blocks = " + std::to_string(blocks) + " must be >= 1");
  if (blocks > kMaxBlocks)
    throw InputError("blocks = " + std::to_string(blocks) + " is more than " + std::to_string(kMaxBlocks));
  sim.check_work(*time);
  const double t0 = sim.time(), target = t0 + *time;
  if (every) {
    // Callback times t0 + k every must increase on the clock: every at least two roundings of
    // the end time (a smaller one would call back at the same time forever).
    const double ulp = std::nextafter(target, INFINITY) - target;
    if (*every < 2 * ulp)
      throw InputError("every = " + number(*every) + " is below the resolution of the clock at time " + number(target) +
                       " (" + number(ulp) + "); callbacks would not advance the run");
    if (*time / *every > kMaxCallbacks)
      throw InputError("every = " + number(*every) + " gives more than " + number(kMaxCallbacks) +
                       " callbacks over time " + number(*time));
  }
}

//! The first chunk's simulated time: about kChunkWork events.
double first_chunk(EventSim& sim, double time) {
  // Chunks of about kChunkWork events, from the event rate of the last chunk; the first from the
  // neighbour-list events alone (one per half shell moved), times a margin for the collisions.
  double speeds = 0;
  for (const Vec3d& v : sim.state()->vel) speeds += norm(v);
  const double rate = 4 * speeds / (0.5 * sim.engine().shell());
  return rate > 0 ? std::min(time, kChunkWork / rate) : time;
}

}  // namespace

void run_event(EventSim& sim, py::object self, std::optional<std::int64_t> steps, std::optional<double> time,
               py::object callback, std::optional<double> every, py::object progress, std::int64_t blocks,
               const TransportArgs& transport_args) {
  const Simulation::InRun in_run(sim);
  check_event_run(sim, steps, time, callback, every, blocks);
  const double t0 = sim.time(), target = t0 + *time;
  TransportSampling transport(sim, transport_args, *time, 0.0);
  std::int64_t sampled = 0;  // transport samples taken
  auto sample_at = [&] {
    if (!transport.on() || sampled >= transport.samples()) return std::numeric_limits<double>::infinity();
    return t0 + double(sampled + 1) * transport.interval();
  };
  double chunk = first_chunk(sim, *time);
  std::int64_t calls = 0;
  auto next_call = [&] {
    if (!every) return target;
    const double t = t0 + double(calls + 1) * *every;
    return t >= target - 1e-9 * *every ? target : t;
  };
  // Blocks end where event_run.cpp ends them: each a block after the last, the last at the end.
  const double block = *time / blocks;
  int closed = 0;
  double block_start = t0;
  auto block_end = [&] { return closed + 1 == blocks ? target : block_start + block; };
  auto close_block = [&] {
    sim.close_block(sim.time() - block_start);
    block_start = sim.time();
    ++closed;
  };
  // A run stopped early (callback, Ctrl-C, error) closes the block it is in, so the next block's
  // counts start where this one's ended.
  auto close_partial = [&] {
    if (closed < blocks && sim.time() > block_start) close_block();
  };
  LoopClock clock(sim);
  try {
    while (sim.time() < target) {
      const double x = sim.time(), call_at = next_call(), block_at = block_end(), t_at = sample_at();
      const double stop = std::min({call_at, block_at, target, t_at});
      double end = std::min(x + chunk, stop);
      // A chunk ends at a stop exactly only if it starts past half of it (Sterbenz), so the
      // state, blocks and callbacks do not depend on where the chunks ended.
      if (end >= stop && x < 0.5 * stop) end = 0.75 * stop;
      const std::int64_t e0 = sim.events();
      {
        Simulation::Running running(sim);
        py::gil_scoped_release release;
        sim.run_until(end, target);
      }
      const double ran = sim.time() - x;
      const std::int64_t ev = sim.events() - e0;
      chunk = ev > 0 ? std::clamp(ran * kChunkWork / double(ev), 0.5 * ran, 4 * ran) : 4 * std::max(ran, chunk);
      if (end == block_at) close_block();
      if (end == t_at) transport.sample(++sampled);
      check_signals();
      if (every && end == call_at) {
        ++calls;
        if (!call_back(clock, callback, self)) break;
      }
      report(clock, progress, std::min(1.0, (sim.time() - t0) / *time), sim.sim_time());
      if (end >= target) break;
    }
  } catch (...) {
    close_partial();
    throw;
  }
  close_partial();
  if (transport.on() && sim.time() >= target) transport.finish();
}

}  // namespace hardsphere::python
