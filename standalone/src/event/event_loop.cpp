#include "event/event_loop.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "event/centre_grid.hpp"
#include "event/renumbering.hpp"
#include "hardsphere/contact_law.hpp"
#include "hardsphere/errors.hpp"
#include "scene/size_classes.hpp"

namespace hardsphere::event {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

double smallest_diameter(const ParticleSystem& sys) {
  double d = kInf;
  for (const double r : sys.radius) d = std::min(d, 2 * r);
  return d;
}

//! The time a sphere takes to fall a distance d from rest, sqrt(d / |g|) (+inf without gravity).
double fall_time(double d, const Physics& physics) {
  if (!physics.has_gravity()) return kInf;
  const Vec3d g{physics.gravity[0], physics.gravity[1], physics.gravity[2]};
  return std::sqrt(d / std::sqrt(dot(g, g)));
}

//! The time a sphere of diameter d takes to cross it at the rms speed or to fall it (`fall`),
//! whichever is shorter (1 for a scene at rest without gravity): events closer than a tiny part
//! of it count as one instant.
double time_scale(const ParticleSystem& sys, double d, double fall) {
  double v2 = 0;
  for (const Vec3d& v : sys.vel) v2 += dot(v, v);
  const double t = std::min(v2 > 0 ? d / std::sqrt(v2 / double(sys.size())) : kInf, fall);
  return t < kInf ? t : 1.0;
}
}  // namespace

EventLoop::EventLoop(const ParticleSystem& sys, const Physics& physics_in, const EventConfig& cfg)
    : max_events_(cfg.max_events) {
  const std::size_t n = sys.size();
  // Physics: validated, then the collision rule's parameters.
  const Physics physics = validated(physics_in, sys.box.periodic);
  // Shaped walls are the stepper's: the event engine predicts contacts with the box faces only.
  if (!physics.shapes.empty())
    throw InputError(physics.shapes.front().source + ": shaped walls run in the stepper only (the event engine " +
                     "predicts contacts with the box faces alone): use the stepper");
  law_.restitution = physics.restitution;
  contact_time_ = physics.contact_time;
  // The smallest diameter's fall time scales the default resting time (hops of ~1e-5 d) and,
  // with the crossing time, the window the jam guard counts as one instant.
  const double d = smallest_diameter(sys), fall = fall_time(d, physics);
  resting_time_ = physics.resting_time > 0 ? physics.resting_time : (fall < kInf ? kRestingTimeFraction * fall : 1.0);
  resting_default_ = !(physics.resting_time > 0), smallest_diameter_ = d;
  if (!physics.elastic()) last_collision_.assign(n, -kInf);
  pair_collisions_.assign(n, 0);
  if (physics.rough()) {
    omega_.assign(n, Vec3d{});
    if (sys.omega.size() == n) omega_ = sys.omega;
    law_.roughness = {physics.tangential_restitution, physics.friction, physics.inertia};
  }
  wall_laws_ = kernel::wall_laws<double>(physics);
  ids_ = &sys.id;
  jam_ = JamGuard(1e-10 * time_scale(sys, d, fall), n);
  mono_ = sys.monodisperse();
  // Geometry: the box, the shell and the cells, sized by the spheres filed in cells (validated).
  const SizeSplit split = split_by_size(sys);
  geometry_ = EventGeometry(sys, cfg, split);
  // Spheres: numbered by cell (big ones last) for the first filing and lists.
  std::vector<Vec3d> pos(n);
  for (std::size_t i = 0; i < n; ++i) pos[i] = geometry_.wrapped(sys.pos[i]);
  trajectories_ = Trajectories(sys, pos, CentreGrid::filing_order(geometry_, pos, split.big), physics);
  // Lists: every list centre at its sphere's position.
  std::vector<Centre> centres(n);
  for (std::size_t k = 0; k < n; ++k)
    centres[k] = Centre{trajectories_[k].x, trajectories_[k].y, trajectories_[k].z, trajectories_[k].r};
  lists_ = NeighbourLists(geometry_, centres, split.big.size());
  predictions_ = Predictions(geometry_, mono_, trajectories_);
  // Predictions: every sphere's first events, once the spheres are numbered for locality.
  renumber();
  for (std::size_t k = 0; k < n; ++k) predict(int(k));
  calendar_.build(predictions_.next_times());
  rebase_every_ = std::max<std::int64_t>(1000, cfg.rebase_events_per_sphere * std::int64_t(n));
}

void EventLoop::run_until(double t_end, double run_end) {
  if (omega_.empty())
    run_until_impl<false>(t_end, run_end);
  else
    run_until_impl<true>(t_end, run_end);
}

template <bool Rough>
void EventLoop::run_until_impl(double t_end, double run_end) {
  // t_end is measured from construction; the calendar from `base_`.
  while (!calendar_.empty() && calendar_.top_key() <= t_end - base_) {
    if (++total_events_ > max_events_) refuse_more_events(run_end);
    step<Rough>();
  }
  now_ = t_end - base_;
  if (transport_) transport_->advance_to(time() - transport_origin_);
}

void EventLoop::run_events(std::int64_t count) {
  if (omega_.empty())
    run_events_impl<false>(count);
  else
    run_events_impl<true>(count);
}

template <bool Rough>
void EventLoop::run_events_impl(std::int64_t count) {
  for (std::int64_t e = 0; e < count && !calendar_.empty() && calendar_.top_key() < kInf; ++e) step<Rough>();
  if (transport_) transport_->advance_to(time() - transport_origin_);
}

const EventCounters& EventLoop::counters() {
  c_.sim_time = time() - reset_time_;
  return c_;
}

void EventLoop::reset_counters() {
  c_ = EventCounters{};
  std::fill(pair_collisions_.begin(), pair_collisions_.end(), std::int64_t(0));
  reset_time_ = time();
}

void EventLoop::set_gravity(const std::array<double, 3>& g) {
  // Trajectories are delayed: each sphere is brought to now on the parabola it flew, then
  // continues on the new one; every prediction assumed the old acceleration.
  rebase();
  trajectories_.rebase(now_);
  trajectories_.set_gravity(g);
  if (resting_default_) {
    Physics p;
    p.gravity = g;
    const double fall = fall_time(smallest_diameter_, p);
    resting_time_ = fall < kInf ? kRestingTimeFraction * fall : 1.0;
  }
  for (std::size_t k = 0; k < trajectories_.size(); ++k) predict(int(k));
  calendar_.build(predictions_.next_times());
}

//! Processes the calendar's first entry.
template <bool Rough>
void EventLoop::step() {
  const int i = int(calendar_.top());
  now_ = calendar_.top_key();
  ++c_.events;
  if (jam_.jammed(base_ + now_)) refuse_jam(i);
  if (predictions_.collision_first(i)) {
    const int j = predictions_.partner(i);
    // Most such entries are valid collisions: request the partner's lines with its counter.
    prefetch(j);
    if (predictions_.stale(i, j)) {
      ++c_.stale_events;
      if (!predictions_.promote_second(i)) predict(i);
      schedule(i);
    } else {
      collide<Rough>(i, j);
    }
  } else {
    boundary_event<Rough>(i);
  }
  if (++events_since_rebase_ >= rebase_every_) rebase();
  // The next event's sphere: its lines load while the loop comes round.
  if (calendar_.empty()) return;
  prefetch(int(calendar_.top()));
  // The event after that is most likely one of the root's children: a whole event's head start.
  for (int k = 0; k < 4; ++k) {
    const std::uint32_t q = calendar_.runner_up(k);
    if (q < trajectories_.size()) prefetch(int(q));
  }
}

void EventLoop::repredict_pair(int i, int j) {
  predictions_.course_changed(i);
  predictions_.course_changed(j);
  predict(i);
  predict(j);
  schedule(i);
  schedule(j);
}

template <bool Rough>
void EventLoop::collide(int i, int j) {
  // Both lists are requested before either is scanned, so their misses overlap. The neighbourhoods are
  // not: each scan requests its partners itself, and doing it here too was slower (see docs/dev/performance.md).
  lists_.prefetch(i);
  lists_.prefetch(j);
  predictions_.prefetch(j);
  calendar_.prefetch(std::uint32_t(i));
  calendar_.prefetch(std::uint32_t(j));
  // Both references ahead of the syncs: with -march=native the compiler fuses multiply-adds by
  // context, and this shape rounds a sync under gravity as the reference runs do.
  Body& a = trajectories_.body(std::size_t(i));
  Body& b = trajectories_.body(std::size_t(j));
  trajectories_.sync(a, now_);
  trajectories_.sync(b, now_);
  Vec3d dr{a.x - b.x, a.y - b.y, a.z - b.z};
  for (int d = 0; d < 3; ++d)  // at contact |dr| <= r_i + r_j < L/2: minimum image
    if (geometry_.periodic(std::size_t(d)))
      dr[d] -= geometry_.len(std::size_t(d)) * std::nearbyint(dr[d] / geometry_.len(std::size_t(d)));
  const std::size_t in_i = trajectories_.input_index(std::size_t(i)), in_j = trajectories_.input_index(std::size_t(j));
  const double t = base_ + now_;
  const kernel::PairRule rule = kernel::pair_rule(
      law_, [&] { return kernel::tc_elastic(t, last_collision_[in_i], last_collision_[in_j], contact_time_); });
  if (law_.restitution != 1.0) last_collision_[in_i] = last_collision_[in_j] = t;
  Vec3d va{a.vx, a.vy, a.vz}, vb{b.vx, b.vy, b.vz};
  const Vec3d va0 = va, vb0 = vb;
  // Exact: an impulse below the rounding of both velocities changes nothing (see collide_pair()).
  const kernel::ContactOutcome out = kernel::collide_pair<Rough, true>(
      law_, rule, dr, va, vb, Rough ? &omega_[in_i] : nullptr, Rough ? &omega_[in_j] : nullptr,
      trajectories_.mass(std::size_t(i)), trajectories_.mass(std::size_t(j)), a.r, b.r, mono_);
  if (!out.changed) {
    // An approach at rounding level, e.g. left by a restitution ~1e-13: it would be predicted
    // again now, without end. The pair slides; its separation is set a hair beyond contact, where
    // its path no longer meets it.
    Trajectories::part(a, b, dr, a.r + b.r);
    ++c_.unresolvable_contacts;
  } else {
    Trajectories::set_velocity(a, va);
    Trajectories::set_velocity(b, vb);
    c_.pair_virial += out.virial;
    if (transport_) {
      transport_->advance_to(t - transport_origin_);
      const double r[3] = {dr.x, dr.y, dr.z};
      transport_->collision(0.0, r, trajectories_.mass(std::size_t(i)), va0, va, trajectories_.mass(std::size_t(j)),
                            vb0, vb);
    }
    if constexpr (Rough) {
      c_.dissipated_normal += out.dissipated_normal;
      c_.dissipated_tangential += out.dissipated_tangential;
    }
    ++c_.collisions;
    ++pair_collisions_[in_i];
    ++pair_collisions_[in_j];
  }
  repredict_pair(i, j);
}

//! Sphere i's wall event: a bounce (the wall law, contact_law.hpp, at the synced contact) or, with
//! no wall axis, leaving its shell.
template <bool Rough>
void EventLoop::boundary_event(int i) {
  Body& s = trajectories_.body(std::size_t(i));
  trajectories_.sync(s, now_);
  const int d = predictions_.wall_axis(i);
  if (d < 0) return rebuild(i);
  const std::size_t a = std::size_t(d);
  const double g = trajectories_.gravity()[a], m = trajectories_.mass(std::size_t(i));
  // The wall it touches: the nearer contact plane.
  const double x = d == 0 ? s.x : (d == 1 ? s.y : s.z);
  const double lo = geometry_.lo(a) + s.r, hi = geometry_.lo(a) + geometry_.len(a) - s.r;
  const int side = std::abs(x - lo) <= std::abs(x - hi) ? -1 : 1;
  const kernel::WallLaw<double>& law = wall_laws_[std::size_t(2 * d + (side > 0))];
  const std::size_t in = trajectories_.input_index(std::size_t(i));
  const double t = base_ + now_;
  // A resting contact leaves at half the speed gravity builds over the resting time and is back
  // after it (the bounces of a sphere at rest would follow each other without end).
  const auto out = kernel::collide_wall<Rough>(
      law, d, side, Vec3d{s.vx, s.vy, s.vz}, g, resting_time_, resting_time_, Rough ? &omega_[in] : nullptr, m, s.r,
      [&] { return kernel::tc_elastic(t, last_collision_[in], last_collision_[in], contact_time_); });
  if (law.restitution != 1.0 && !out.rested) last_collision_[in] = t;
  if (out.rested || out.restituted) {  // on the contact plane, leaving at out.leave
    trajectories_.rest(s, a, out.leave, geometry_);
    if (out.rested) ++c_.resting_contacts;
  } else {
    trajectories_.reflect(s, a, geometry_);
  }
  if (!out.rested) ++c_.wall_collisions;
  if constexpr (Rough) {
    Trajectories::set_velocity(s, Vec3d{s.vx, s.vy, s.vz} + out.dv);
    c_.dissipated_normal += out.contact.dissipated_normal;
    c_.dissipated_tangential += out.contact.dissipated_tangential;
  }
  c_.wall_dissipated_normal += out.contact.dissipated_normal;
  c_.wall_dissipated_tangential += out.contact.dissipated_tangential;
  c_.wall_impulse[a] += m * out.impulse;
  predictions_.course_changed(i);
  predict(i);
  schedule(i);
}

//! Sphere i (synced) has left its shell: new list centre at its position (wrapped into the
//! box) and new list. Its trajectory is unchanged, so its candidates stay valid and only the
//! new members are scanned.
void EventLoop::rebuild(int i) {
  ++c_.neighbour_list_rebuilds;
  const bool wrapped = trajectories_.wrap_into_box(std::size_t(i), geometry_);
  const Body& s = trajectories_[std::size_t(i)];
  predictions_.set_list_centre(i, s.x, s.y, s.z);
  const std::vector<std::uint32_t>& fresh = lists_.rebuild(i, Centre{s.x, s.y, s.z, s.r}, wrapped);
  if (predictions_.best_is_stale(i) && !predictions_.promote_second(i))
    predict(i);
  else
    predictions_.predict_new_members(i, trajectories_, fresh.data(), int(fresh.size()), now_);
  schedule(i);
}

//! Every event of sphere i predicted afresh.
void EventLoop::predict(int i) {
  ++c_.full_predictions;
  trajectories_.sync(trajectories_.body(std::size_t(i)), now_);
  predictions_.predict(i, trajectories_, lists_.entries(i), lists_.size(i), now_);
}

void EventLoop::schedule(int i) { calendar_.update(std::uint32_t(i), predictions_.next_time(i)); }

//! Moves every sphere to the current time and shifts the clock so that now = 0.
void EventLoop::rebase() {
  events_since_rebase_ = 0;
  if (now_ == 0) return;
  trajectories_.rebase(now_);
  predictions_.shift_times(now_);
  calendar_.shift_keys(now_);
  base_ += now_;
  now_ = 0;
  renumber();
}

//! Renumbers the spheres in the lists' locality order. Spheres wander away from their
//! neighbours in memory as they diffuse; this restores locality. Any time will do: only indices
//! change, not the physics.
void EventLoop::renumber() {
  const Renumbering r(lists_.locality_order());
  trajectories_.permute(r);
  predictions_.permute(r);
  lists_.permute(r);
  calendar_.build(predictions_.next_times());
}

void EventLoop::refuse_more_events(double t_end) const {
  std::ostringstream m;
  m << "event engine: the run needs more than " << max_events_ << " events (it had reached time " << base_ + now_
    << " of " << t_end << "); shorten the run";
  throw InputError(m.str());
}

void EventLoop::refuse_jam(int i) const {
  const auto id = [this](int k) { return (*ids_)[trajectories_.input_index(std::size_t(k))]; };
  if (predictions_.collision_first(i)) jam_.refuse("event engine", id(i), id(predictions_.partner(i)));
  if (predictions_.wall_axis(i) >= 0) jam_.refuse("event engine", id(i), -1);
  // Neighbour-list rebuilds at one instant: no chain, a sphere too fast for the clock.
  const Body& b = trajectories_[std::size_t(i)];
  jam_.refuse_fast("event engine", id(i), std::sqrt(b.vx * b.vx + b.vy * b.vy + b.vz * b.vz), 0.5 * geometry_.shell(),
                   base_ + now_);
}

}  // namespace hardsphere::event
