#pragma once
//! Exact event-driven molecular dynamics (EDMD) of hard spheres.
//!
//! Every sphere moves in a straight line between events. Three kinds of event are predicted and
//! executed in time order: pair collisions (contact time from kernel::contact_time, impulse from
//! kernel::collide / collide_equal_mass), wall collisions and cell crossings. Each sphere holds
//! exactly one entry in the event calendar (its earliest predicted event); an entry naming a
//! partner is stale once that partner has collided since (per-sphere collision counters), and a
//! stale entry is simply re-predicted when it comes up. Positions are "delayed": each sphere
//! stores its position at its own last update time and is advanced only when it takes part in an
//! event or is observed. The clock is re-based to zero every few events per sphere so long runs
//! keep full precision.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hardsphere/particles.hpp"

namespace hardsphere {

//! Which engine a run uses.
enum class Engine { Stepper, Event };
Engine parse_engine(const std::string& s);  //!< "stepper" or "event"; throws InputError

struct EventConfig {
  //! Cells per axis; 0 = auto (as many as fit with width >= the largest diameter, at most
  //! max_cells_per_sphere * N cells). Periodic axes need at least 3 cells.
  std::array<int, 3> cells{0, 0, 0};
  double max_cells_per_sphere = 2.0;
  //! Stencil half-width in cells: cells are at least (largest diameter / reach) wide and a sphere's
  //! partners are searched (2 reach + 1)^3 cells around it. 2 halves the volume searched (fewer
  //! candidates) at the price of twice as many cell crossings and 125 cells per scan; measured
  //! 20-30% slower at phi = 0.45, so 1 is the default. Periodic axes need 2 reach + 1 cells.
  int reach = 1;
  //! Events per sphere between re-basings of the clock (all spheres brought to the current time,
  //! times shifted to zero).
  std::int64_t rebase_events_per_sphere = 64;
};

struct EventCounters {
  double sim_time = 0;                //!< simulated time since the last reset
  std::int64_t collisions = 0;        //!< pair collisions executed
  std::int64_t wall_collisions = 0;   //!< wall reflections executed
  std::int64_t cell_crossings = 0;    //!< cell crossings executed
  std::int64_t stale_events = 0;      //!< calendar entries found stale and re-predicted
  std::int64_t events = 0;            //!< all calendar entries processed (the four above)
  std::int64_t full_predictions = 0;  //!< predictions that scanned all 27 cells around a sphere
  double pair_virial = 0;             //!< sum over collisions of r_ij . dp_i (>= 0)
  std::array<double, 3> wall_impulse{0, 0, 0};  //!< momentum given to the walls of each axis
};

class EventEngine {
 public:
  //! Validates (throws InputError: overlaps, periodic axes shorter than 3 largest diameters).
  explicit EventEngine(const ParticleSystem& sys, const EventConfig& cfg = {});
  ~EventEngine();
  EventEngine(const EventEngine&) = delete;
  EventEngine& operator=(const EventEngine&) = delete;

  //! Runs all events up to `duration` later; the state is then exactly at that time.
  void advance(double duration);
  //! Runs until the next `count` events have been processed (or nothing is left to happen).
  void advance_events(std::int64_t count);

  //! The state at the current time, in input order, periodic coordinates wrapped.
  ParticleSystem state() const;
  const EventCounters& counters() const;
  void reset_counters();
  double time() const;  //!< simulated time since construction
  std::array<int, 3> cells_per_dim() const;
  std::string scene_kernel() const;  //!< e.g. "periodic,mono"

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hardsphere
