#pragma once
//! Dense amorphous packings of equal spheres (docs/initial_states.md).
//!
//! Random centres are separated by a soft-sphere quench (fire_quench.hpp), straight at the
//! target up to direct_limit. Denser targets start from a quench at anneal_start and are
//! approached in compression stages, in the spirit of Lubachevsky-Stillinger: hard-sphere
//! dynamics (the event engine) for a fixed number of events per sphere lets the packing relax,
//! the spheres grow by a small step in packing fraction and a short quench removes the overlaps
//! the growth made. A stage that fails is retried from the last good packing, relaxed again,
//! with half the step; the number of stages is bounded.
#include <cstdint>
#include <vector>

#include "hardsphere/box.hpp"
#include "hardsphere/rng.hpp"
#include "hardsphere/vec3.hpp"
#include "init/fire_quench.hpp"

namespace hardsphere {

struct DensePackingConfig {
  QuenchConfig quench;                   //!< the first quench, from random centres
  std::int64_t stage_iterations = 2000;  //!< FIRE steps allowed per compression stage
  double direct_limit = 0.60;            //!< targets up to this are quenched straight from random centres
  double anneal_start = 0.56;            //!< denser targets: first quench here, then compression stages
  double first_step = 0.005;             //!< packing-fraction step of the compression stages
  double min_step = 0.0005;              //!< give up when a stage fails with a step this small
  double events_per_sphere = 100;        //!< hard-sphere events between stages
  int max_stages = 60;
  double final_events_per_sphere = 200;  //!< hard-sphere events relaxing the final packing
  double final_inflation = 0.002;        //!< eps of the quench that separates its contacts
};

struct DensePackingStats {
  QuenchStats quench;       //!< all FIRE work
  int stages = 0;           //!< compression stages tried
  std::int64_t events = 0;  //!< hard-sphere events run
  double densest = 0;       //!< densest packing fraction reached without overlap
};

//! n centres for spheres of the given radius, no overlap (gaps of at least eps/2 diameters, see
//! fire_quench.hpp), deterministic for a given rng state. Throws InputError naming the packing
//! fraction asked for and the densest reached when the target cannot be reached.
std::vector<Vec3d> dense_packing(const Box& box, std::int64_t n, double radius, Rng& rng,
                                 const DensePackingConfig& cfg = {}, DensePackingStats* stats = nullptr);

}  // namespace hardsphere
