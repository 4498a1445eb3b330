// The event engine in the run driver: equilibration and the measured run in simulated time, the
// latter split into blocks for the error bars of Z and of the collision rate.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/observables.hpp"
#include "hardsphere/precision.hpp"
#include "hardsphere/scene_limits.hpp"
#include "run/engine_run.hpp"
#include "run/rotation_reach.hpp"

namespace hardsphere {

namespace {

//! Mean and standard error of the mean of block values.
std::pair<double, double> mean_error(const std::vector<double>& x) {
  const double n = double(x.size());
  if (x.empty()) return {0, 0};
  double m = 0;
  for (double v : x) m += v;
  m /= n;
  if (x.size() < 2) return {m, 0};
  double s = 0;
  for (double v : x) s += (v - m) * (v - m);
  return {m, std::sqrt(s / (n - 1) / n)};
}

class EventRun final : public EngineRun {
 public:
  explicit EventRun(const RunSpec& spec) : spec_(spec) {
    if (!(spec.time > 0) || !std::isfinite(spec.time))
      throw InputError("time = " + std::to_string(spec.time) +
                       " must be positive and finite (event engine runs for a simulated time)");
    if (!(spec.equilibrate_time >= 0) || !std::isfinite(spec.equilibrate_time))
      throw InputError("equilibrate time = " + std::to_string(spec.equilibrate_time) + " must be >= 0");
    if (spec.blocks < 1) throw InputError("blocks = " + std::to_string(spec.blocks) + " must be >= 1");
  }

  void start(const ParticleSystem& sys) override {
    EventConfig cfg = spec_.event;
    cfg.max_events = spec_.work_limit;
    engine_ = std::make_unique<EventEngine>(sys, spec_.physics, cfg);
    check_event_work(sys, engine_->shell(), spec_.time + spec_.equilibrate_time, spec_.work_limit, spec_.physics);
    n_ = sys.size();
  }
  const char* name() const override { return "event"; }
  double measured_time() const override { return spec_.time; }
  double time_quantum() const override { return 0; }
  void check_track_every(double) const override {}  // the state is exact at any time
  ParticleSystem state() const override { return engine_->state(); }
  bool equilibrate() override {
    if (!(spec_.equilibrate_time > 0)) return false;
    engine_->advance(spec_.equilibrate_time);
    return true;
  }
  void reset_counters() override { engine_->reset_counters(); }
  double measure(const RunOutputs& out) override;
  RunTotals totals(double kinetic0, const Vec3d& momentum0) const override {
    return run_totals(engine_->counters(), kinetic0, momentum0);
  }
  // The event engine computes in double whatever the stepper's precision.
  double rounding_epsilon() const override { return hardsphere::rounding_epsilon(Precision::Double); }
  void add_summary(nlohmann::json& j, const ParticleSystem& fin, double cpu) const override;
  std::string final_title() const override {
    return "hardsphere state after event-driven time " + std::to_string(engine_->counters().sim_time);
  }

 private:
  //! Runs `duration` further, stopping at each tracker row's time on the way (samples change
  //! nothing). A row due within rounding of the end is taken there.
  void advance(double duration, Tracker* tracker);
  //! advance(), stopping at each transport sample on the way.
  void advance(double duration, Tracker* tracker, TransportRun* transport);

  const RunSpec& spec_;
  std::unique_ptr<EventEngine> engine_;
  std::size_t n_ = 0;
  double t_measure_ = 0;
  std::int64_t next_transport_ = 1;  // the next transport sample's index
  std::optional<BlockAverages> blocks_;
};

void EventRun::advance(double duration, Tracker* tracker) {
  const double end = engine_->time() + duration;
  if (tracker) {
    for (double t = tracker->next_time(); t_measure_ + t <= end + 1e-9 * tracker->every(); t = tracker->next_time()) {
      engine_->advance(std::max(0.0, std::min(t_measure_ + t, end) - engine_->time()));
      tracker->write(t, engine_->sphere(tracker->index()));
    }
  }
  engine_->advance(std::max(0.0, end - engine_->time()));
}

void EventRun::advance(double duration, Tracker* tracker, TransportRun* transport) {
  if (!transport) return advance(duration, tracker);
  const double end = engine_->time() + duration;
  for (;;) {
    const std::int64_t k = next_transport_;
    const double t = t_measure_ + double(k) * transport->interval();
    if (k > transport->samples() || t > end) break;
    advance(std::max(0.0, t - engine_->time()), tracker);
    transport->sample(k, engine_->state());
    ++next_transport_;
  }
  advance(std::max(0.0, end - engine_->time()), tracker);
}

double EventRun::measure(const RunOutputs& out) {
  // A dump frame (if asked for) after each block.
  blocks_.emplace(engine_->state());
  double cpu = 0;
  t_measure_ = engine_->time();
  if (out.transport) {
    out.transport->begin(engine_->state());
    engine_->set_transport(&out.transport->tally());
    next_transport_ = 1;
  }
  const double block = spec_.time / spec_.blocks;
  for (int b = 0; b < spec_.blocks; ++b) {
    const double t_start = engine_->time();
    const double target = b + 1 == spec_.blocks ? spec_.time - engine_->counters().sim_time : block;
    const double c0 = process_cpu_seconds();
    advance(target, out.tracker, out.transport);
    cpu += process_cpu_seconds() - c0;
    const EventCounters& c = engine_->counters();
    blocks_->close_block(c, engine_->time() - t_start);
    if (out.dump) out.dump->write_frame(c.events, engine_->state());
    if (out.progress) (*out.progress)(double(b + 1) / spec_.blocks, c.sim_time);
  }
  if (out.transport) engine_->set_transport(nullptr);
  return cpu;
}

void EventRun::add_summary(nlohmann::json& j, const ParticleSystem&, double cpu) const {
  add_event_summary(j, *engine_, spec_.equilibrate_time, cpu);
  if (blocks_) blocks_->add_summary(j);
}

}  // namespace

std::unique_ptr<EngineRun> make_event_run(const RunSpec& spec) { return std::make_unique<EventRun>(spec); }

//! A sphere re-lists its neighbours each time it has moved half the shell: at least
//! sum |v_i| t / (shell / 2) events, whatever collisions add (rough spheres: the speed their
//! rotation can become, rotation_reach). Refuse up front what the engine's event limit would
//! stop later.
void check_event_work(const ParticleSystem& sys, double shell, double time, double limit,
                      const std::array<double, 3>& gravity) {
  Physics smooth;
  smooth.gravity = gravity;
  check_event_work(sys, shell, time, limit, smooth);
}

void check_event_work(const ParticleSystem& sys, double shell, double time, double limit, const Physics& physics) {
  const std::array<double, 3>& gravity = physics.gravity;
  const RotationReach spin = rotation_reach(sys, physics);
  double speeds = spin.sum;
  double bounces = wall_bounce_rate(sys) * time;
  // Under gravity a sphere falls across its gap G (at most the box) and bounces at least every
  // 2 sqrt(2 G / g), reaching speeds up to sqrt(2 g G): more bounces and list events.
  double fall = 0;  // along periodic axes (a chute) a sphere may fall freely: g t^2 / 2
  for (int d = 0; d < 3; ++d) {
    const double g = std::abs(gravity[std::size_t(d)]);
    if (g == 0) continue;
    if (sys.box.periodic[std::size_t(d)]) {
      fall += double(sys.size()) * 0.5 * g * time * time;
      continue;
    }
    const double gap = std::max(sys.box.length(d) - 2 * sys.max_radius(), 1e-300);
    bounces += double(sys.size()) * time * std::sqrt(g / (8 * gap));
    speeds += double(sys.size()) * std::sqrt(2 * g * gap);
  }
  const double events = (speeds * time + fall) / (0.5 * shell) + bounces;
  if (events > limit) {
    // Most of it from rotation: name the spin that the clock could not follow.
    const bool by_rotation = spin.from_spin * time / (0.5 * shell) > 0.5 * events;
    std::ostringstream m;
    m << "the run would take " << (by_rotation ? "about " : "at least ") << events << " events (" << sys.size()
      << " spheres moving " << speeds * time + fall << " in all over time " << time;
    if (by_rotation)
      m << ", as fast as rough collisions can turn rotation into speed (" << spin.describe(sys) << " alone up to "
        << std::hypot(norm(sys.vel[spin.sphere]),
                      std::sqrt(physics.inertia) * sys.radius[spin.sphere] * norm(sys.omega[spin.sphere]))
        << ")";
    m << ", a neighbour-list event every " << 0.5 * shell;
    if (bounces > 0) m << ", and " << bounces << " wall bounces";
    m << "), more than the limit of " << limit << "; shorten --time, lower the speeds"
      << (by_rotation ? ", the angular velocities" : "") << " or the gravity";
    throw InputError(m.str());
  }
}

BlockAverages::BlockAverages(const ParticleSystem& start)
    : n_(start.size()), temperature_(n_ ? 2 * kinetic_energy(start) / (3.0 * double(n_)) : 0.0) {}

void BlockAverages::close_block(const EventCounters& c, double dt) {
  z_.push_back(compressibility_factor(c.pair_virial - virial_, dt, n_, temperature_));
  rate_.push_back(dt > 0 && n_ ? 2.0 * double(c.collisions - collisions_) / (double(n_) * dt) : 0.0);
  virial_ = c.pair_virial;
  collisions_ = c.collisions;
}

void BlockAverages::add_summary(nlohmann::json& j) const {
  j["blocks"] = blocks();
  j["collision_rate_error"] = mean_error(rate_).second;
  j["compressibility_factor_error"] = mean_error(z_).second;
}

}  // namespace hardsphere
