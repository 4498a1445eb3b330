#pragma once
//! The event-driven engine's event handling: the calendar's earliest entry executed, one after
//! the other (a pair collision, a wall collision or a list rebuild, then the new predictions of
//! the spheres it concerns; a stale entry is predicted again). It keeps the clock, re-based to
//! zero every few events per sphere (and the spheres then renumbered along the cells for memory
//! locality) so long runs keep full precision, and the counters.
#include <cstdint>
#include <limits>
#include <vector>

#include "common/always_inline.hpp"
#include "common/jam_guard.hpp"
#include "event/event_calendar.hpp"
#include "event/geometry.hpp"
#include "event/neighbour_lists.hpp"
#include "event/prediction.hpp"
#include "event/trajectories.hpp"
#include "hardsphere/contact_law.hpp"
#include "hardsphere/event_engine.hpp"
#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"

namespace hardsphere::event {

class EventLoop {
 public:
  //! The spheres of sys (in id order) at time 0 with their first events predicted. Throws
  //! InputError for invalid physics or a box without room for the cells and a shell. sys must
  //! outlive the loop: its ids name atoms in messages.
  EventLoop(const ParticleSystem& sys, const Physics& physics, const EventConfig& cfg);

  //! Runs every event up to t_end (time since construction); the state is then at t_end.
  //! Throws InputError past EventConfig::max_events, naming `run_end` as the end of the run.
  void run_until(double t_end, double run_end);
  //! Runs the next `count` events, or fewer if nothing is left to happen.
  void run_events(std::int64_t count);

  double time() const { return base_ + now_; }  //!< time since construction
  double now() const { return now_; }           //!< time of the clock the trajectories run on
  const EventGeometry& geometry() const { return geometry_; }
  const Trajectories& trajectories() const { return trajectories_; }
  const EventCounters& counters();
  //! By input index, since the last reset_counters().
  const std::vector<std::int64_t>& pair_collisions() const { return pair_collisions_; }
  //! By input index: the angular velocities of rough spheres (empty when smooth).
  const std::vector<Vec3d>& omega() const { return omega_; }
  void reset_counters();
  //! Gravity `g` (validated) from now on: every sphere synced to now on its old parabola, the
  //! default resting time rescaled, every event predicted afresh.
  void set_gravity(const std::array<double, 3>& g);
  //! The transport tally, its clock 0 at the current time (EventEngine::set_transport).
  void set_transport(TransportTally* tally) {
    transport_ = tally;
    transport_origin_ = time();
  }

 private:
  // inline: the handlers of one event are one hot path, compiled together in event_loop.cpp.
  //! Rough: the spheres rotate (a loop of its own, so the smooth one compiles as without them).
  template <bool Rough>
  inline void step();
  template <bool Rough>
  void run_until_impl(double t_end, double run_end);
  template <bool Rough>
  void run_events_impl(std::int64_t count);
  //! A pair collision: the pair law (contact_law.hpp) at the synced contact.
  template <bool Rough>
  inline void collide(int i, int j);
  //! After a pair collision or parting: both spheres' next events predicted and scheduled.
  inline void repredict_pair(int i, int j);
  template <bool Rough>
  inline void boundary_event(int i);
  inline void rebuild(int i);
  inline void predict(int i);
  inline void schedule(int i);
  //! Requests what an event of sphere i reads first (its list's address needs no load: it is
  //! scanned if the sphere collides).
  HS_ALWAYS_INLINE void prefetch(int i) const {
    trajectories_.prefetch(std::size_t(i));
    predictions_.prefetch(i);
    lists_.prefetch(i);
  }
  void rebase();
  void renumber();
  [[noreturn]] void refuse_more_events(double t_end) const;
  [[noreturn]] void refuse_jam(int i) const;

  EventGeometry geometry_;
  Trajectories trajectories_;
  NeighbourLists lists_;
  Predictions predictions_;
  EventCalendar calendar_;  // each sphere's earliest predicted event

  bool mono_ = true;
  kernel::PairLaw<double> law_;  // restitution (1: elastic) and the tangential law (rough only)
  double contact_time_ = 0.0;
  std::array<kernel::WallLaw<double>, 6> wall_laws_{};  // the box faces' (kFaceNames order)
  double resting_time_ = 0;                             // Physics::resting_time (or its default)
  bool resting_default_ = false;                        // resting_time_ is the default: it follows |g|
  double smallest_diameter_ = 0;                        // scales the default resting time
  std::vector<double> last_collision_;                  // input index: time of the last collision (restitution < 1)
  std::vector<std::int64_t> pair_collisions_;           // input index: pair collisions since reset_counters()
  std::vector<Vec3d> omega_;                            // input index: angular velocities (rough only)
  const std::vector<std::int64_t>* ids_ = nullptr;      // input index: atom id (the caller's), for messages
  JamGuard jam_;

  double now_ = 0, base_ = 0, reset_time_ = 0;
  TransportTally* transport_ = nullptr;  // set_transport: told of the time and every collision
  double transport_origin_ = 0;
  std::int64_t events_since_rebase_ = 0, rebase_every_ = 0;
  double total_events_ = 0;  // all events since construction
  double max_events_ = std::numeric_limits<double>::infinity();
  EventCounters c_;
};

}  // namespace hardsphere::event
