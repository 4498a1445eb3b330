#pragma once
//! Exact event-driven molecular dynamics (EDMD) of hard spheres.
//!
//! Every sphere moves in a straight line between events. Three kinds of event are predicted and
//! executed in time order: pair collisions (contact time from kernel::contact_time, impulse from
//! kernel::collide / collide_equal_mass), wall collisions and neighbour-list rebuilds.
//! Neighbour lists: each sphere has a list centre (its position when its list was made) and
//! lists every sphere whose centre is closer than sigma_ij + shell to its own (symmetric: j is
//! in i's list iff i is in j's). A sphere rebuilds its list when it has moved shell/2 from its
//! centre, so while neither of two unlisted spheres has rebuilt they are more than sigma_ij
//! apart: every collision is between listed spheres, and predictions scan only the list. The
//! cell grid (width >= largest diameter + shell) files spheres by list centre, is consulted only
//! by rebuilds and is never crossed. Spheres over two median diameters (at most the 256 largest,
//! "big") are not filed and do not size the grid: every rebuild tests their centres, and a big
//! sphere's rebuild scans all the cells its range overlaps. Each sphere holds exactly one entry
//! in the event calendar (its earliest predicted event); an entry naming a partner is stale once
//! that partner has collided since (per-sphere collision counters), and a stale entry is
//! re-predicted when it comes up (or replaced by the stored second-best candidate). Positions
//! are "delayed": each sphere stores its position at its own last update time and is advanced
//! only when it takes part in an event or is observed. The clock is re-based to zero every few
//! events per sphere (and the spheres renumbered in Morton order of their cells) so long runs
//! keep full precision.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"
#include "hardsphere/transport.hpp"

namespace hardsphere {

//! Neighbour-list shell in largest diameters for a gas at packing fraction phi: about 1.6 mean
//! free paths, within [0.6, 2].
double auto_shell(double phi);

struct EventConfig {
  //! Cells per axis of the grid that finds neighbour-list members (spheres are filed by their
  //! list centre); 0 = auto (as many as fit with width >= (largest diameter + shell) / reach,
  //! at most max_cells_per_sphere * reach^3 * N cells). Periodic axes need 2 reach + 1 cells.
  //! Here and below "largest diameter" leaves out the big spheres.
  std::array<int, 3> cells{0, 0, 0};
  double max_cells_per_sphere = 2.0;
  //! Stencil half-width in cells for list rebuilds: cells are at least (largest diameter +
  //! shell) / reach wide and a rebuild searches (2 reach + 1)^3 cells. 2 searches a smaller
  //! volume through 125 cells; rebuilds are a small part of the events, so 1 is the default
  //! (docs/event_engine.md).
  int reach = 1;
  //! Neighbour-list shell in units of the largest diameter: a sphere's list holds every sphere
  //! whose list centre is closer than sigma_ij + shell to its own, and is rebuilt when the
  //! sphere has moved shell / 2 from its centre. Shrunk automatically when a periodic axis or
  //! a user-given cell grid is too small for it. 0 = auto_shell(packing fraction): 0.6 in dense
  //! gases (where the optimum of timed runs is flat, docs/event_engine.md), thicker in dilute ones,
  //! where free flights are long and a thin shell means several rebuilds per collision.
  double shell = 0;
  //! Events per sphere between re-basings of the clock (all spheres brought to the current time,
  //! times shifted to zero).
  std::int64_t rebase_events_per_sphere = 64;
  //! The most events the engine may process since construction before it refuses to go on
  //! (InputError); a guard against runs that would not end.
  double max_events = std::numeric_limits<double>::infinity();
  //! How the adapter names the physics settings, for the advice of a refusal (e.g. which
  //! contact time lets an inelastic collapse through).
  PhysicsNames names;
};

struct EventCounters {
  double sim_time = 0;                //!< simulated time since the last reset
  std::int64_t collisions = 0;        //!< pair collisions executed
  std::int64_t wall_collisions = 0;   //!< wall reflections executed
  std::int64_t resting_contacts = 0;  //!< wall contacts too slow to bounce (Physics::resting_time)
  //! Pair contacts approaching below the rounding of their velocities (no impulse changes them):
  //! set a hair apart instead of collided.
  std::int64_t unresolvable_contacts = 0;
  std::int64_t cell_crossings = 0;              //!< always 0: cells hold list centres, which never cross
  std::int64_t neighbour_list_rebuilds = 0;     //!< spheres that left their shell and were re-listed
  std::int64_t stale_events = 0;                //!< calendar entries found stale and re-predicted
  std::int64_t events = 0;                      //!< all calendar entries processed (collisions, walls, rebuilds, stale)
  std::int64_t full_predictions = 0;            //!< predictions that scanned a sphere's whole neighbour list
  double pair_virial = 0;                       //!< sum over collisions of r_ij . dp_i (>= 0)
  std::array<double, 3> wall_impulse{0, 0, 0};  //!< momentum given to the walls of each axis
  //! Kinetic energy the collisions took, by channel; rough scenes only (as StepCounters').
  double dissipated_normal = 0, dissipated_tangential = 0;
  double wall_dissipated_normal = 0, wall_dissipated_tangential = 0;  //!< as StepCounters'
  std::int64_t kinematic_collisions = 0;  //!< always 0: the event engine refuses kinematic spheres
  double kinematic_work = 0;
};

class EventEngine {
 public:
  //! Validates (throws InputError: overlaps, periodic axes shorter than 3 largest diameters of
  //! the spheres that are not big, or not longer than twice the two largest radii plus a shell).
  explicit EventEngine(const ParticleSystem& sys, const Physics& physics = {}, const EventConfig& cfg = {});
  ~EventEngine();
  EventEngine(const EventEngine&) = delete;
  EventEngine& operator=(const EventEngine&) = delete;

  //! Runs all events up to `duration` later; the state is then exactly at that time. A caller
  //! that splits a longer run passes its end as `run_end`, the time the work-limit refusal names.
  void advance(double duration, std::optional<double> run_end = std::nullopt);
  //! Runs until the next `count` events have been processed (or nothing is left to happen).
  void advance_events(std::int64_t count);

  //! The state at the current time, ordered by id (as the stepper's), periodic coordinates wrapped.
  ParticleSystem state() const;
  const EventCounters& counters() const;
  //! The sphere at position `index` of state() (id order) at the current time, without
  //! advancing the others. Throws InputError for an index out of range.
  SphereSample sphere(std::size_t index) const;
  //! Each sphere's pair collisions since the last reset_counters(), in id order; they add
  //! up to twice counters().collisions.
  std::vector<std::int64_t> pair_collisions_per_sphere() const;
  void reset_counters();
  //! Changes gravity from the current time on (a rotating drum's): every sphere continues from
  //! where it is on a parabola of the new acceleration and every event is predicted afresh, so
  //! the run stays exact. Validated as validated_gravity() (InputError naming EventConfig::names'
  //! gravity). A default resting time (Physics::resting_time 0) follows the new |g|.
  void set_gravity(const std::array<double, 3>& g);
  std::array<double, 3> gravity() const;  //!< the acceleration in use (as validated)
  //! Feeds `tally` (started by the caller from state(), its clock 0 now; nullptr: none) with the
  //! time and every pair collision, so its stress and heat-flux integrals are exact (transport.hpp).
  void set_transport(TransportTally* tally);
  double time() const;  //!< simulated time since construction
  std::array<int, 3> cells_per_dim() const;
  double shell() const;              //!< neighbour-list shell in use (length units, after any shrinking)
  std::string scene_kernel() const;  //!< e.g. "periodic,mono"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hardsphere
