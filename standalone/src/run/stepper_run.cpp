// The stepper in the run driver: a run of whole steps, measured in chunks between dump frames,
// tracker rows and progress reports (chunks change nothing: the engine carries its whole state).
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "hardsphere/errors.hpp"
#include "hardsphere/scene_limits.hpp"
#include "hardsphere/stepper.hpp"
#include "run/engine_run.hpp"
#include "run/rotation_reach.hpp"

namespace hardsphere {

namespace {

class StepperRun final : public EngineRun {
 public:
  explicit StepperRun(const RunSpec& spec) : spec_(spec), dt_(spec.stepper.dt) {
    if (spec.steps < 0) throw InputError("steps = " + std::to_string(spec.steps) + " must be >= 0");
    if (spec.equilibrate < 0) throw InputError("equilibrate = " + std::to_string(spec.equilibrate) + " must be >= 0");
    if (spec.dump && spec.dump_every < 1)
      throw InputError("dump every = " + std::to_string(spec.dump_every) + " must be >= 1");
  }

  void start(const ParticleSystem& sys) override {
    StepperConfig cfg = spec_.stepper;
    cfg.max_particle_steps = spec_.work_limit;
    cfg.count_per_sphere = cfg.count_per_sphere || spec_.track_id.has_value();
    engine_ = make_stepper(sys, spec_.physics, cfg, spec_.precision);
    check_stepper_work(*engine_, spec_.stepper, sys, spec_.steps + spec_.equilibrate, spec_.work_limit, spec_.physics);
  }
  const char* name() const override { return "stepper"; }
  double measured_time() const override { return double(spec_.steps) * dt_; }
  double time_quantum() const override { return dt_; }
  void check_track_every(double every) const override {
    // Rows are written at the ends of steps, so they must be a whole number of steps apart.
    const double ratio = every / dt_;
    track_steps_ = std::llround(ratio);
    if (!(std::isfinite(ratio) && ratio >= 0.5 && std::abs(ratio - double(track_steps_)) <= 1e-9 * ratio)) {
      std::ostringstream m;
      m << "--track-every " << every << " is not a whole number of steps of --dt " << dt_;
      throw InputError(m.str());
    }
  }
  ParticleSystem state() const override { return engine_->state(); }
  bool equilibrate() override {
    if (spec_.equilibrate == 0) return false;
    engine_->run(spec_.equilibrate);
    return true;
  }
  void reset_counters() override { engine_->reset_counters(); }
  double measure(const RunOutputs& out) override;
  RunTotals totals(double kinetic0, const Vec3d& momentum0) const override {
    return run_totals(engine_->counters(), kinetic0, momentum0);
  }
  double rounding_epsilon() const override { return hardsphere::rounding_epsilon(spec_.precision); }
  void add_summary(nlohmann::json& j, const ParticleSystem& fin, double cpu) const override;
  std::string final_title() const override {
    return "hardsphere state after " + std::to_string(engine_->counters().steps) + " steps";
  }

 private:
  const RunSpec& spec_;
  double dt_;
  std::unique_ptr<StepperBase> engine_;
  mutable std::int64_t track_steps_ = 0;
};

double StepperRun::measure(const RunOutputs& out) {
  const std::int64_t steps = spec_.steps;
  double cpu = 0;
  std::int64_t done = 0;
  if (out.tracker) out.tracker->write(0.0, engine_->sphere(out.tracker->index()));
  const std::int64_t report_every = out.progress ? std::max<std::int64_t>(1, steps / 100) : steps;
  std::int64_t next_frame = out.dump ? std::min(spec_.dump_every, steps) : steps;
  std::int64_t next_sample = out.tracker ? std::min(track_steps_, steps) : steps;
  // Transport samples every `every` steps (a whole number: TransportRun rounds its interval to dt).
  const std::int64_t every = out.transport ? std::llround(out.transport->interval() / dt_) : steps;
  std::int64_t next_transport = out.transport ? std::min(every, steps) : steps;
  if (out.transport) {
    out.transport->begin(engine_->state());
    engine_->set_transport(&out.transport->tally());
  }
  while (done < steps) {
    const std::int64_t chunk =
        std::min({next_frame - done, next_sample - done, next_transport - done, report_every, steps - done});
    const double t0 = process_cpu_seconds();
    engine_->run(chunk);
    cpu += process_cpu_seconds() - t0;
    done += chunk;
    if (out.dump && done == next_frame) {
      out.dump->write_frame(done, engine_->state());
      next_frame = std::min(next_frame + spec_.dump_every, steps);
    }
    if (out.tracker && done == next_sample) {
      if (done % track_steps_ == 0) out.tracker->write(double(done) * dt_, engine_->sphere(out.tracker->index()));
      next_sample = std::min(next_sample + track_steps_, steps);
    }
    if (out.transport && done == next_transport) {
      if (done / every <= out.transport->samples()) out.transport->sample(done / every, engine_->state());
      next_transport = std::min(next_transport + every, steps);
    }
    if (out.progress) (*out.progress)(double(done) / double(steps), engine_->counters().sim_time);
  }
  if (out.transport) engine_->set_transport(nullptr);
  return cpu;
}

void StepperRun::add_summary(nlohmann::json& j, const ParticleSystem& fin, double cpu) const {
  add_stepper_summary(j, *engine_, spec_.stepper, spec_.precision, fin, spec_.equilibrate, cpu);
  add_shape_summary(j, spec_.physics, engine_->counters());
}

}  // namespace

std::unique_ptr<EngineRun> make_stepper_run(const RunSpec& spec) { return std::make_unique<StepperRun>(spec); }

void check_stepper_work(const StepperBase& engine, const StepperConfig& cfg, const ParticleSystem& sys,
                        std::int64_t steps, double work_limit, const Physics& physics) {
  const double dt = cfg.dt;
  // Flights between walls barely wider than a sphere bounce many times per step: refuse steps
  // that would run into the per-step event limit, and count the bounces as work.
  const double bounces = wall_bounce_rate(sys) * dt;
  if (bounces > double(cfg.max_events_per_step)) {
    std::ostringstream m;
    m << "spheres between walls barely wider than them would bounce " << bounces << " times per step of dt = " << dt
      << ", more than the limit of " << cfg.max_events_per_step
      << " events per step; use a smaller --dt or wider walls";
    throw InputError(m.str());
  }
  double substeps = engine.substeps_per_step();
  const RotationReach spin = rotation_reach(sys, physics);
  const bool by_rotation = engine.substeps_at(spin.speed) > substeps;
  if (by_rotation) substeps = engine.substeps_at(spin.speed);
  const double work = double(sys.size()) * double(steps) * substeps + bounces * double(steps);
  if (work > work_limit) {
    std::ostringstream m;
    m << "the run would take " << work << " particle-steps (" << sys.size() << " spheres, " << steps << " steps";
    if (by_rotation)
      m << " of " << substeps << " sub-steps each: with dt = " << dt << ", rough collisions can turn the rotation of "
        << spin.describe(sys) << " into a speed of " << spin.speed
        << ", which moves more than half the pair-list skin (" << engine.skin() << ") per step";
    else if (substeps > 1)
      m << " of " << substeps << " sub-steps each: with dt = " << dt
        << " the fastest sphere moves more than half the pair-list skin (" << engine.skin() << ") per step";
    m << "), more than the limit of " << work_limit << "; use fewer steps"
      << (by_rotation    ? ", a smaller dt or smaller angular velocities"
          : substeps > 1 ? " or a smaller dt"
                         : "");
    throw InputError(m.str());
  }
}

void add_stepper_warnings(nlohmann::json& j, const StepperBase& engine, const StepperConfig& cfg,
                          const ParticleSystem& fin) {
  const StepCounters& c = engine.counters();
  if (c.unresolved_steps > 0)
    j["warnings"].push_back(std::to_string(c.unresolved_steps) + " steps stopped at the limit of " +
                            std::to_string(cfg.max_events_per_step) +
                            " contact events per step with contacts left unresolved (spheres may overlap): the "
                            "spheres are jammed or collapsing; use a smaller --dt or a less dense state");
  if (!engine.sweep_detection()) {
    // Overlap detection misses grazes, more of them the further spheres move per step.
    double v2 = 0, dmin = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < fin.size(); ++i)
      v2 += dot(fin.vel[i], fin.vel[i]), dmin = std::min(dmin, 2 * fin.radius[i]);
    const double move = fin.size() ? std::sqrt(v2 / double(fin.size())) * cfg.dt : 0.0;
    if (move > kOverlapDetectionLimit * dmin) {
      // Auto decides at every list rebuild, so it can end a run in overlap mode just before
      // switching; name what was in use and a remedy that changes it.
      const bool automatic = cfg.detect == Detect::Auto;
      std::ostringstream m;
      m << (automatic ? "--detect auto ended the run in overlap mode" : "--detect overlap")
        << " with steps that move a sphere at the rms speed by " << move / dmin << " diameters (more than "
        << kOverlapDetectionLimit
        << "): grazes within a step are missed (0.5-0.8% of the collisions at 0.14 diameters, more for longer "
           "steps); "
        << (automatic ? "use --detect sweep" : "use --detect sweep or auto");
      j["warnings"].push_back(m.str());
    }
  }
}

}  // namespace hardsphere
