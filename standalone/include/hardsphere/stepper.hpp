#pragma once
//! The time-stepped, a posteriori hard-sphere engine of the seed paper.
//!
//! One step: drift every sphere by v dt; then find every overlapping *approaching* pair (and
//! every wall a sphere has crossed), rewind each to its exact contact time, apply the elastic
//! impulse and re-advance. Contacts are resolved earliest first from a time-bucketed queue;
//! after each collision the two spheres' contacts over the rest of the step are predicted
//! again (their straight-line motion since the collision), so nothing is dropped or taken out
//! of order.
//!
//! Contacts are found through a cell grid: every few steps the spheres are sorted by cell
//! (one array per field, reordered for locality) and a candidate pair list with a skin is
//! built from neighbouring cells; in between only the list is scanned. The list is rebuilt
//! as soon as two unlisted spheres could have closed the gap between them, so no contact is
//! ever missed.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "hardsphere/particles.hpp"
#include "hardsphere/physics.hpp"
#include "hardsphere/precision.hpp"
#include "hardsphere/transport.hpp"

namespace hardsphere {

Precision parse_precision(const std::string& s);

//! How contacts are found at the end of a step. Overlap: the seed's a posteriori test (pairs
//! that overlap now), plus a sweep of the neighbours of every colliding sphere so contacts are
//! resolved in time order. Sweep: every candidate pair is tested for a contact anywhere within
//! the step, so grazes and pass-throughs inside one step are caught too. Auto: sweep when steps
//! are long enough for grazes to matter (v_rms dt > 0.1 of the smallest diameter), otherwise overlap;
//! decided again at every list rebuild, as the speeds change.
enum class Detect { Overlap, Sweep, Auto };
//! Auto sweeps when a sphere at the rms speed moves more than this many smallest diameters per
//! step; overlap detection's missed grazes are measurable beyond it.
constexpr double kOverlapDetectionLimit = 0.1;
Detect parse_detect(const std::string& s);
//! Whether mode d detects by sweeping for this system and step (Auto decided from its speeds).
bool detects_by_sweep(Detect d, const ParticleSystem& sys, double dt);

struct StepperConfig {
  double dt = 0.01;
  //! Cells per axis; 0 means "auto" (the ideal number of boxes for N, box, diameter and the
  //! per-step displacement). The diameter is the largest but for big spheres (over two median
  //! diameters, at most 256), which find their pairs by a pass of their own when the periodic
  //! axes are long enough for it. {1,1,1} is the seed's one-box O(N^2) baseline.
  std::array<int, 3> cells{0, 0, 0};
  //! Contact events per step before giving up (counted in StepCounters::unresolved_steps);
  //! only an inelastic collapse could need more.
  std::int64_t max_events_per_step = 100000000;
  Detect detect = Detect::Auto;
  //! Select kernels specialised for the scene (no wall tests in periodic boxes, no per-sphere
  //! radii and masses when all are equal). false runs the general kernel on any scene: only
  //! for measuring what the specialisation gains, results are the same.
  bool specialise = true;
  //! Rebuild the pair list only when an unlisted pair could have closed its gap (the sum of the
  //! two spheres' displacements, checked for the few spheres past half the skin), instead of
  //! when any sphere has moved half the skin. false keeps that classic test: only for measuring
  //! what the pairwise test gains; the collisions are the same.
  bool pairwise_list_check = true;
  //! The most particle-steps (sub-steps included) the engine may take before it refuses to go
  //! on (InputError); a guard against runs that would not end.
  double max_particle_steps = std::numeric_limits<double>::infinity();
  //! Packing fraction of the gas for the auto skin and the kernel choice; 0: the box's. An
  //! adapter whose box has empty margins (one MPI rank's spheres and ghosts) passes the whole
  //! gas's, so its stepper is tuned like one over the whole gas.
  double packing_fraction = 0.0;
  //! Wall axes whose walls no sphere reaches while the stepper runs, because its adapter makes a
  //! new stepper before any could (one MPI rank's box, walled beyond its ghosts): no wall tests
  //! along them. A sphere found beyond such a wall at a pair-list rebuild throws std::logic_error.
  std::array<bool, 3> unreached_walls{false, false, false};
  //! Count each sphere's pair collisions (StepperBase::sphere(), pair_collisions_per_sphere()).
  //! Off by default: two scattered increments per collision cost dense gases a few per cent.
  bool count_per_sphere = false;
  //! How the adapter names the physics settings, for the advice of a refusal (e.g. which
  //! contact time lets an inelastic collapse through).
  PhysicsNames names;
};

struct StepCounters {
  std::int64_t steps = 0;
  double sim_time = 0;
  std::int64_t collisions = 0;       //!< pair collisions resolved
  std::int64_t wall_collisions = 0;  //!< wall reflections
  //! Wall contacts under gravity too slow to bounce (slower than gravity speeds a sphere up in one
  //! sub-step): the sphere rests on the wall to the end of the sub-step, which carries its weight.
  std::int64_t resting_contacts = 0;
  std::int64_t rebuilds = 0;          //!< cell sorts + pair-list builds
  std::int64_t unresolved_steps = 0;  //!< steps that hit max_events_per_step with contacts left
  //! Sub-steps taken: a step in which the fastest sphere would move half the skin or more is
  //! split, so the pair list covers every path (equal to steps when no step needed it).
  std::int64_t substeps = 0;
  //! Sub-steps ended early, at a collision that sent a sphere too fast for the list's skin
  //! (the rest of the sub-step is run again in shorter pieces).
  std::int64_t step_cuts = 0;
  double pair_virial = 0;                                      //!< sum over collisions of r_ij . dp_i (>= 0)
  std::array<double, 6> pair_virial_tensor{0, 0, 0, 0, 0, 0};  //!< r_ij (x) dp_i: xx yy zz xy xz yz
  std::array<double, 3> wall_impulse{0, 0, 0};                 //!< momentum given to the walls of each axis
  //! Kinetic energy the collisions took, by channel (normal, tangential); counted in rough scenes
  //! only (0 in smooth ones, whose loss is the change of the kinetic energy).
  double dissipated_normal = 0, dissipated_tangential = 0;
  //! What the walls took: restitution and resting contacts' net (normal), friction (tangential).
  double wall_dissipated_normal = 0, wall_dissipated_tangential = 0;
  //! Free spheres' bounces off kinematic spheres (resting ones are resting_contacts) and the work
  //! the kinematic spheres did on them (ParticleSystem::kinematic).
  std::int64_t kinematic_collisions = 0;
  double kinematic_work = 0;
  //! The work moving shaped walls did on the spheres (Physics::shapes; 0 for walls at rest).
  double wall_work = 0;
  //! Each shaped wall's collisions, resting contacts and work (Physics::shapes order).
  std::vector<WallShapeTotals> shapes;
};

//! Type-erased engine interface, so precision and scene specialisations are chosen at run time.
//! Adapters that mirror the spheres reach them through state_exchange() (state_exchange.hpp).
class StepperBase {
 public:
  virtual ~StepperBase() = default;
  virtual void run(std::int64_t steps) = 0;
  virtual ParticleSystem state() const = 0;  //!< ordered by id, periodic coordinates wrapped
  virtual const StepCounters& counters() const = 0;
  virtual void reset_counters() = 0;
  virtual std::array<int, 3> cells_per_dim() const = 0;
  virtual double skin() const = 0;
  virtual std::string scene_kernel() const = 0;  //!< which specialisation runs, e.g. "periodic,mono"
  virtual bool sweep_detection() const = 0;      //!< the detection mode in use (Auto resolved) is sweep
  //! Sub-steps the next step needs at the current speeds (1 unless dt is long for the skin).
  virtual double substeps_per_step() const = 0;
  //! Sub-steps a step needs while a sphere moves at `speed` (the same rule).
  virtual double substeps_at(double speed) const = 0;
  //! An upper bound of every sphere's speed during the last step (collisions and gravity
  //! included), so that speed times dt bounds every sphere's move in it.
  virtual double step_speed_bound() const = 0;
  //! The sphere at position `index` of state() (id order), in O(1) between list rebuilds, so a
  //! tracker can follow it every few steps. Throws InputError for an index out of range.
  virtual SphereSample sphere(std::size_t index) const = 0;
  //! Each sphere's pair collisions since the last reset_counters(), ordered like state(); they
  //! add up to twice counters().collisions. Empty unless StepperConfig::count_per_sphere.
  virtual std::vector<std::int64_t> pair_collisions_per_sphere() const = 0;
  //! Changes gravity between steps (a rotating drum's, LAMMPS's variable fix gravity): the
  //! following steps' flights are parabolas in the new acceleration, so each step stays exact.
  //! Validated as validated_gravity() (InputError naming StepperConfig::names' gravity).
  virtual void set_gravity(const std::array<double, 3>& g) = 0;
  //! The acceleration the next step uses (as validated: rounding-level components zero).
  virtual std::array<double, 3> gravity() const = 0;
  //! Changes shaped wall k's angular velocity (Physics::shapes[k].omega) between steps: a LAMMPS
  //! region turned by a variable angle, its rate over the next step. Throws InputError for a
  //! non-finite rate and std::out_of_range for a k that is not a wall.
  virtual void set_shape_rotation(std::size_t k, double omega) = 0;
  //! Feeds `tally` (started by the caller from state(); nullptr: none) with every step's time and
  //! every pair collision, so its stress and heat-flux integrals are exact (transport.hpp).
  virtual void set_transport(TransportTally* tally) = 0;
};

//! Validates the physics and the configuration against the system (throws InputError) and builds
//! the engine.
std::unique_ptr<StepperBase> make_stepper(const ParticleSystem& sys, const Physics& physics, const StepperConfig& cfg,
                                          Precision precision = Precision::Double);

}  // namespace hardsphere
