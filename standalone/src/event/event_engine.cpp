#include "hardsphere/event_engine.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "common/jam_guard.hpp"
#include "common/neighbour_entry.hpp"
#include "event/event_loop.hpp"
#include "hardsphere/errors.hpp"
#include "hardsphere/scene_limits.hpp"

namespace hardsphere {

double auto_shell(double phi) {
  // A sphere rebuilds its list after moving shell / 2, so rebuilds per collision grow as the mean
  // free path lambda = sigma / (6 sqrt(2) phi g(sigma)) (Enskog, Carnahan-Starling g) outgrows the
  // shell. So the shell follows lambda: 1.6 lambda (where timed runs found the optimum), kept within
  // [0.6, 2] diameters (see docs/dev/performance.md).
  if (!(phi > 0)) return 0.6;
  const double g = (1 - phi / 2) / std::pow(1 - std::min(phi, 0.7), 3);
  const double lambda = 1 / (6 * std::sqrt(2.0) * phi * g);
  return std::clamp(1.6 * lambda, 0.6, 2.0);
}

namespace {
//! The spheres in id order: the engine's "input" order, so that state() comes out as the
//! stepper's does and the same spheres give the same run in whatever order they are handed over.
ParticleSystem sorted_by_id(const ParticleSystem& sys) {
  const std::vector<std::size_t> order = order_by_id(sys.id);
  bool sorted = true;
  for (std::size_t k = 0; k < order.size() && sorted; ++k) sorted = order[k] == k;
  if (sorted) return sys;
  ParticleSystem out;
  out.box = sys.box;
  out.reserve(sys.size());
  for (const std::size_t i : order)
    out.push_back(sys.id[i], sys.type[i], sys.radius[i], sys.mass[i], sys.pos[i], sys.vel[i],
                  i < sys.image.size() ? sys.image[i] : std::array<std::int32_t, 3>{0, 0, 0},
                  i < sys.omega.size() ? sys.omega[i] : Vec3d{});
  if (sys.source_line.size() == sys.size()) {
    out.source = sys.source;
    for (const std::size_t i : order) out.source_line.push_back(sys.source_line[i]);
    if (sys.velocity_line.size() == sys.size())
      for (const std::size_t i : order) out.velocity_line.push_back(sys.velocity_line[i]);
  }
  return out;
}

//! The spheres checked (consistent, representable, few enough to index) and sorted by id, with
//! the configuration's own limits checked; the rest is the physics' and the geometry's.
ParticleSystem validated_spheres(const ParticleSystem& sys_in, const EventConfig& cfg, bool rough) {
  if (sys_in.radius.size() != sys_in.size() || sys_in.mass.size() != sys_in.size() ||
      sys_in.vel.size() != sys_in.size() || sys_in.id.size() != sys_in.size() || sys_in.type.size() != sys_in.size())
    throw InputError("event engine: inconsistent particle arrays");
  // Kinematic spheres need contact times with one sphere falling and the other not (a quartic) in
  // every prediction; the stepper finds them at each contact instead.
  if (sys_in.kinematic_count())
    throw InputError("event engine: kinematic spheres (" + std::to_string(sys_in.kinematic_count()) +
                     ") are followed by the stepper only; run them with the stepper");
  ParticleSystem sys = sorted_by_id(sys_in);
  const std::size_t n = sys.size();
  if (n > std::size_t(kMaxAdjIndex) + 1)  // indices 0 .. kMaxAdjIndex fit a list entry
    throw InputError("too many spheres for the event engine: " + std::to_string(n) + " (at most " +
                     std::to_string(std::size_t(kMaxAdjIndex) + 1) + ")");
  check_scene_numbers(sys, "event engine");
  check_engine_numbers<double>(sys, 0, "event engine", 0, rough);
  if (!(cfg.max_events > 0)) throw InputError("event engine: max_events must be positive");
  if (!(cfg.shell >= 0) || !std::isfinite(cfg.shell))
    throw InputError("event engine: shell " + std::to_string(cfg.shell) + " must be positive (or 0 for auto)");
  sys.image.resize(n, {0, 0, 0});
  sys.omega.resize(n);
  return sys;
}
}  // namespace

struct EventEngine::Impl {
  Impl(const ParticleSystem& sys, const Physics& physics, const EventConfig& cfg)
      : proto(sys),
        loop(proto, physics, cfg),
        collapse_advice(hardsphere::collapse_advice(physics, cfg.names)),
        names(cfg.names) {}
  //! Runs f, completing a jam refusal in the face's words.
  template <class F>
  void guarded(F&& f) {
    try {
      f();
    } catch (const JammedSpheres& e) {
      if (collapse_advice.empty()) throw;
      throw JammedSpheres(e.what() + collapse_advice);
    }
  }
  // ids, types, radii, masses, input images and (smooth spheres) spins in input order (positions
  // unused); before the loop, which names atoms by its ids.
  ParticleSystem proto;
  event::EventLoop loop;
  std::string collapse_advice;  // added to a jam refusal (inelastic collisions)
  PhysicsNames names;           // the adapter's, for set_gravity's refusals
};

EventEngine::EventEngine(const ParticleSystem& sys, const Physics& physics, const EventConfig& cfg)
    : impl_(std::make_unique<Impl>(validated_spheres(sys, cfg, physics.rough()), physics, cfg)) {}

EventEngine::~EventEngine() = default;

void EventEngine::advance(double duration, std::optional<double> run_end) {
  if (!(duration >= 0) || !std::isfinite(duration))
    throw InputError("event engine: run time " + std::to_string(duration) + " must be finite and >= 0");
  const double end = time() + duration;
  impl_->guarded([&] { impl_->loop.run_until(end, run_end.value_or(end)); });
}

void EventEngine::advance_events(std::int64_t count) {
  impl_->guarded([&] { impl_->loop.run_events(count); });
}

ParticleSystem EventEngine::state() const {
  ParticleSystem out = impl_->proto;
  out.source.clear(), out.source_line.clear(), out.velocity_line.clear();  // the engine's state, not the file's
  impl_->loop.trajectories().observe(impl_->loop.now(), out);
  // Smooth spheres keep the spins they were given (proto's), bit for bit.
  const std::vector<Vec3d>& omega = impl_->loop.omega();
  if (!omega.empty()) out.omega = omega;
  wrap_periodic(out);
  return out;
}

SphereSample EventEngine::sphere(std::size_t index) const {
  const std::size_t n = impl_->proto.size();
  if (index >= n)
    throw InputError("sphere index " + std::to_string(index) + " is out of range (" + std::to_string(n) + " spheres)");
  SphereSample out = impl_->loop.trajectories().sample(index, impl_->loop.now(), impl_->proto);
  out.pair_collisions = impl_->loop.pair_collisions()[index];
  return out;
}

std::vector<std::int64_t> EventEngine::pair_collisions_per_sphere() const { return impl_->loop.pair_collisions(); }

const EventCounters& EventEngine::counters() const { return impl_->loop.counters(); }

void EventEngine::reset_counters() { impl_->loop.reset_counters(); }

void EventEngine::set_gravity(const std::array<double, 3>& g) {
  impl_->loop.set_gravity(validated_gravity(g, impl_->names));
}

void EventEngine::set_transport(TransportTally* tally) { impl_->loop.set_transport(tally); }

std::array<double, 3> EventEngine::gravity() const { return impl_->loop.trajectories().gravity(); }

double EventEngine::time() const { return impl_->loop.time(); }

std::array<int, 3> EventEngine::cells_per_dim() const { return impl_->loop.geometry().cells(); }

double EventEngine::shell() const { return impl_->loop.geometry().shell(); }

std::string EventEngine::scene_kernel() const {
  return std::string(impl_->proto.box.all_periodic() ? "periodic" : "walls") +
         (impl_->proto.monodisperse() ? ",mono" : ",poly");
}

}  // namespace hardsphere
