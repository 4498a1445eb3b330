#pragma once
//! How fix hardsphere advances the atoms: on one rank the standalone stepper over all of them
//! (SerialPath), under MPI (or 'path ghosts') one stepper per rank over its owned atoms and the
//! ghosts around its sub-domain (GhostPath). The fix talks to either through this interface and
//! totals the steps in one place.
#include <array>
#include <string>

#include "hardsphere/collision_totals.hpp"
#include "hardsphere/physics.hpp"
#include "hardsphere/stepper.hpp"

namespace LAMMPS_NS {

//! What an error about an invalid state tells the user to do: at a run's start, and after
//! another fix moved atoms at the end of a step.
inline constexpr char kStartHint[] = "start from a valid non-overlapping state";
inline constexpr char kMovedAtomsHint[] = "a fix that moves atoms must leave them apart (and inside fixed walls)";
inline constexpr char kInsertedAtomsHint[] =
    "a fix that inserts atoms must place them apart from the others and inside fixed walls (fix deposit: 'near' at "
    "least the largest contact distance)";

//! What one step did on this rank (weighted by ownership on the owned + ghost path, so the sums
//! over ranks are the totals).
struct StepTotals : hardsphere::WeightedCollisionTotals {
  double unresolved = 0;  //!< steps that hit max_events with contacts left
  bool rerun = false;     //!< re-run for all atoms at once (a ghost disagreed)
};

//! What changed since the last step, as the fix knows it.
struct StepStart {
  bool without_setup = false;  //!< the first step of a 'run ... pre no'
  bool others_acted = false;   //!< another fix may have changed velocities at the end of the last step
  std::string moved_by;        //!< non-empty: another fix moved atoms (names it and the step, for errors)
};

class StepPath {
 public:
  virtual ~StepPath() = default;
  //! The settings of every stepper the path makes from now on.
  virtual void configure(const hardsphere::StepperConfig &config, const hardsphere::Physics &physics) = 0;
  //! Gravity from the next step on (a fix gravity with variables, validated): the stepper in use
  //! and every one the path makes later.
  virtual void set_gravity(const std::array<double, 3> &g) = 0;
  //! Shaped wall k's angular velocity from the next step on (a region's 'rotate v_theta'): the
  //! stepper in use and every one the path makes later.
  virtual void set_shape_rotation(std::size_t k, double omega) = 0;
  //! LAMMPS re-neighboured (or a run's setup does): it may have wrapped, sorted or migrated atoms.
  virtual void neighbours_changed() = 0;
  //! A run's setup: the path starts from LAMMPS's atoms, checked as a run's start.
  virtual void run_starts() = 0;
  //! Before each step: takes up what changed since the last. Returns whether the velocities were
  //! read anew from LAMMPS's rows (the temperature is then measured again from them).
  virtual bool before_step(const StepStart &start) = 0;
  //! One step. `virial_rows` (6 per owned LAMMPS row, or nullptr) receives each owned atom's share
  //! of its collision virial, times `scale`.
  virtual StepTotals step(double *virial_rows, double scale) = 0;
  //! Sum of m v^2 over this rank's owned atoms as the last step left them.
  virtual double owned_mv2() const = 0;
  //! Whether LAMMPS must re-neighbour in this step (the path needs fresh ghosts).
  virtual bool needs_reneighbor() const = 0;
  //! A run ends: LAMMPS's rows hold the final state afterwards.
  virtual void run_ends() = 0;
  //! LAMMPS's forward communication of the fix (the owned + ghost path's ghost velocities, and
  //! angular velocities for rough spheres).
  virtual int pack_forward(int, int *, double *, int, const int *) { return 0; }
  virtual void unpack_forward(int, int, double *) {}
  static constexpr int kForwardSize = 3;
  static constexpr int forward_size(bool rough) { return rough ? 2 * kForwardSize : kForwardSize; }
};

}  // namespace LAMMPS_NS
