#pragma once
//! fix ID all hardsphere [detect overlap|sweep] [max_events N] [ghost auto|user] [path auto|ghosts]
//!
//! Time integrator for hard spheres (instead of fix nve/sphere); user documentation in
//! docs/fix_hardsphere.md. On one rank it hands the atoms to the standalone stepper
//! (fix_hardsphere_serial.cpp). Under MPI (or 'path ghosts') it drifts the owned atoms by v dt and
//! mirrors them at fixed (f) box faces (LAMMPS keeps atoms inside), then undoes the mirrors and
//! resolves the step's collisions and wall bounces in time order with hardsphere::ContactResolver
//! (the standalone stepper's implementation) over owned + ghost atoms, checks the ghosts against
//! their owners and re-runs the step for all atoms if they disagree. What it refuses (other fixes,
//! boundaries, minimize, ...) is decided in fix_hardsphere_checks.cpp. Global vector
//! (f_ID[1..10]): collisions (cumulative), collisions in the last step, sum of r_ij.dp_i over
//! collisions, simulated time, wall bounces, steps re-run for all atoms at once because a ghost
//! copy disagreed with its owner, forced reneighbourings, steps that hit max_events,
//! compressibility factor Z and pressure P (time averages since the fix was defined).
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "contact_resolver.hpp"
#include "fix.h"
#include "hardsphere/stepper.hpp"

namespace LAMMPS_NS {

class FixHardSphere : public Fix {
 public:
  FixHardSphere(class LAMMPS *, int, char **);
  ~FixHardSphere() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void setup_pre_neighbor() override;
  void pre_neighbor() override;
  void initial_integrate(int) override;
  void post_run() override;
  void post_force(int) override;
  void reset_dt() override;
  double compute_vector(int) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  double memory_usage() override;

 private:
  using V3 = hardsphere::Vec3<double>;
  template <bool Mono>
  struct Hooks;
  template <bool Mono>
  void resolve_step(hardsphere::ContactResolver<double, Mono> &res);
  void record_build();
  void build_adjacency();
  void check_setup();
  // fix_hardsphere_checks.cpp: what the fix refuses, and the neighbour settings it needs.
  void check_input();
  void check_other_fixes();
  void apply_neighbor_settings();
  //! 2 KE / (3 N) over all atoms (the standalone's temperature: 3N degrees of freedom).
  double temperature_now() const;
  //! Whether another fix may have changed velocities at the end of `step`.
  bool others_acted(bigint step) const;
  void on_collision(int i, int j, double back);
  bool ghosts_agree_with_owners();
  void resolve_globally();
  // Serial path (fix_hardsphere_serial.cpp): the standalone stepper on the owned atoms.
  void serial_setup();
  void serial_step();
  void serial_map();
  void serial_map_if_stale();
  void map_tags();
  void serial_follow_lammps();
  void serial_write();
  void serial_schedule();
  bool serial_must_write() const;
  //! The LAMMPS box as a hardsphere::Box, no spheres yet.
  hardsphere::ParticleSystem empty_system() const;
  //! A standalone stepper for `sys` with this fix's dt, detection mode and event limit.
  std::unique_ptr<hardsphere::StepperBase> new_stepper(const hardsphere::ParticleSystem &sys) const;
  void unmirror(int k);
  void note_disp(int k, const V3 &p);

  class NeighList *list = nullptr;
  double dt = 0.0;
  bool sweep = false;
  bool ghost_auto = true;
  double ghost_factor = 2.0;
  bool mono = false;
  double mono_sigma = 0.0, mono_mass = 0.0;
  std::int64_t max_events = 100000000;

  // Serial runs (one rank) hand the owned atoms to the standalone stepper, which handles
  // periodic images itself: no ghosts, no neighbour list, the standalone result by construction.
  // 'path ghosts' forces the owned + ghost path (the MPI one) in serial too.
  bool ghost_path_only = false;
  bool serial = false;
  std::unique_ptr<hardsphere::StepperBase> stepper;
  std::vector<std::int64_t> slot_id;           //!< scratch: the stepper's atom tags, slot order
  std::vector<std::int32_t> slot_image;        //!< scratch: the stepper's wrap counts, 3 per slot
  std::vector<std::uint32_t> slot_local;       //!< stepper slot -> LAMMPS local index
  std::vector<V3> slot_shift;                  //!< LAMMPS position - stepper position, per slot
  std::vector<V3> slot_pos, slot_vel;          //!< scratch: the stepper's state while mapping
  std::vector<std::uint32_t> local_slot;       //!< LAMMPS local index -> stepper slot
  std::vector<imageint> mapped_image;          //!< LAMMPS's image flags the shifts account for
  std::vector<int> tag_local;                  //!< atom tag -> LAMMPS local index, as of mapped_tags
  std::vector<tagint> mapped_tags;             //!< LAMMPS's tags in local order when tag_local was made
  std::vector<std::array<int, 3>> tag_image0;  //!< per tag: LAMMPS unwrapped = stepper unwrapped + this * L
  std::vector<double> v_written;               //!< velocities last written, while other fixes may change them
  bool others_every_step = false;              //!< another fix acts inside every step
  std::vector<int> others_every;               //!< nevery of other fixes acting only at end_of_step
  std::int64_t slot_rebuilds = -1;             //!< stepper rebuilds when the slots were mapped
  bool slots_dirty = true;                     //!< slot_local/slot_shift need serial_map()
  bool lammps_moved = false;                   //!< LAMMPS re-neighboured: it may have wrapped or sorted atoms
  bool state_written = true;                   //!< LAMMPS's x and v hold the stepper's current state

  double *wall_axes = nullptr;  //!< per atom: bit d set if the drift of this step mirrored it on axis d

  // Cross-check of ghost copies against their owners (see ghosts_agree_with_owners).
  int comm_mode = 0;                    //!< forward comm: 0 velocity + wall_axes, 1 owners' final velocity
  std::vector<std::uint8_t> met_owned;  //!< per ghost: collided with an owned atom in this step
  std::vector<V3> v_owner;              //!< per ghost: its owner's velocity at the end of the step
  double **start = nullptr;             //!< per atom: this step's drift displacement, velocity before it
  std::vector<V3> x_start;              //!< scratch: owned positions at the start of the step
  double n_wall_start = 0;
  bool adjacency_dirty = true;

  // Local (owned + ghost) arrays for the resolver.
  std::vector<V3> pos, vel, vprev, xbuild;
  std::vector<double> rad, mass;
  std::vector<std::int64_t> tags;
  std::vector<std::uint32_t> adj_start, adj;  // adj: hardsphere::adj_entry(partner, image)
  V3 zero_shift[27];
  hardsphere::ContactResolver<double, true> res_mono;
  hardsphere::ContactResolver<double, false> res_poly;

  // Per-step and cumulative tallies (local: each collision is counted on the rank owning the
  // atom with the smaller tag; compute_vector sums over ranks).
  double step_virial[6] = {0, 0, 0, 0, 0, 0};
  double max_disp2 = 0.0;
  double n_coll = 0, n_coll_step = 0, virial_sum = 0, n_wall = 0, n_global = 0, n_forced = 0, n_unresolved = 0;
  double sim_time = 0.0;
  // Time-averaged temperature for Z and P (f_ID[9], f_ID[10]): collisions keep the kinetic
  // energy, so the temperature is recomputed only when something else may have changed it.
  double t_now = 0.0;        //!< current temperature, 2 KE / (3 N)
  double t_integral = 0.0;   //!< sum over steps of t_now * dt (since the fix was defined)
  bool run_set_up = false;   //!< setup() ran for this run ('run ... pre no' skips it)
  bool neigh_noted = false;  //!< the neighbour settings message was printed
};

}  // namespace LAMMPS_NS
