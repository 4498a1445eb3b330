#pragma once
//! fix ID all hardsphere [detect overlap|sweep] [max_events N] [restitution e] [contact_time tc]
//!                       [tangential_restitution beta] [friction mu] [inertia q]
//!                       [ghost auto|user] [path auto|ghosts] [timing no|yes]
//!
//! Time integrator for hard spheres (instead of fix nve/sphere); user documentation in
//! docs/fix_hardsphere.md. The fix is LAMMPS's face: it reads its keywords, refuses what it
//! cannot simulate (fix_hardsphere_checks.cpp), hands each step to a StepPath (step_path.h: the
//! standalone stepper on one rank, serial_path.h; one stepper per rank over owned and ghost atoms
//! under MPI, ghost_path.h) and totals the steps. Global vector (f_ID[1..10]): collisions
//! (cumulative), collisions in the last step, sum of r_ij.dp_i over collisions, simulated time,
//! wall bounces, steps re-run for all atoms at once because a ghost copy disagreed with its owner,
//! forced reneighbourings, steps that hit max_events, compressibility factor Z and pressure P
//! (time averages since the fix was defined).
#include <array>
#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "fix.h"
#include "hardsphere/physics.hpp"
#include "hardsphere/stepper.hpp"
#include "other_fixes.h"
#include "part_timer.h"
#include "step_path.h"

namespace LAMMPS_NS {

class FixHardSphere : public Fix {
 public:
  FixHardSphere(class LAMMPS *, int, char **);
  ~FixHardSphere() override;
  int setmask() override;
  void init() override;
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
  // The per-atom collision virial of the last step (see vstep) follows LAMMPS's atoms.
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  double memory_usage() override;
  //! Refuses (error->all) the other fixes fix hardsphere cannot follow (fix_hardsphere_checks.cpp).
  //! Also called by pair_style hardsphere before it refuses an empty box: the box may be empty
  //! because such a fix (fix pour) would fill it, and that is the cause to name.
  void check_other_fixes();

 private:
  void check_other_fix(class Fix *f, int mask);  //!< one other fix, by its style and mask
  void check_setup();
  void check_contact_distances();  //!< pair_coeff against the atoms and those fixes insert
  void check_timestep() const;
  //! The last step's collision virial, as LAMMPS's virial (energy units) when it asks, global
  //! and per atom.
  void report_step_virial(int vflag);
  //! Whether this step's per-atom virial is asked for (compute stress/atom and the like).
  bool wants_atom_virial(int vflag) const;
  //! Adds one step's totals to the fix's outputs.
  void add_step(const StepTotals &t);
  // fix_hardsphere_checks.cpp: what the fix refuses, and the neighbour settings it needs.
  void check_input();
  //! A run without setup: the fixes must be those the last init() checked.
  void check_fixes_unchanged();
  void check_big_spheres_mpi();
  //! Refuses a ghost cutoff (LAMMPS's contact distance + skin, comm_modify cutoff, the owned +
  //! ghost path's shell `shell`) beyond kMaxGhostBoxes periodic box lengths, before LAMMPS copies
  //! every atom into each image within it.
  void check_ghost_cutoff(double shell) const;
  void apply_neighbor_settings();
  void skip_reverse_comm();
  //! The summed acceleration of the fix gravity commands (refused along periodic axes).
  void read_gravity();
  //! The summed acceleration of the fix gravity commands as they are now (`settled`: only those
  //! whose vector is set, see read_gravity()).
  std::array<double, 3> gravity_now(bool settled) const;
  //! Before each step: a fix gravity with variables evaluated them at the end of the last step
  //! (post_force); the step's flights take that acceleration, constant within the step.
  void take_gravity();
  //! The warning of a chute that cannot reach a steady state (hardsphere::unbounded_flow), once a run.
  void warn_unbounded_flow();
  bool flow_warned = false;
  void read_walls();  //!< the walls of the fix wall/hardsphere(/region) commands into physics
  //! Before each step: a turning region's walls take its angle's rate over the step.
  void take_wall_turns();
  std::string walls_text() const;  //!< those walls in words, to see whether they changed
  //! A wall keyword at arg[a]: 'KEY value' (every wall) or 'KEY face value'; returns the
  //! arguments it took.
  int wall_keyword(int a, int narg, char **arg);
  //! How the fix's messages name the physics settings.
  static hardsphere::PhysicsNames physics_names() {
    hardsphere::PhysicsNames n;
    n.restitution = "restitution", n.contact_time = "contact_time", n.gravity = "fix gravity";
    n.walls = "'boundary f' on that axis";
    n.tangential_restitution = "tangential_restitution", n.friction = "friction", n.inertia = "inertia";
    n.wall_restitution = "wall_restitution", n.wall_tangential_restitution = "wall_tangential_restitution";
    n.wall_friction = "wall_friction", n.face_separator = " ";
    return n;
  }
  //! 2 KE / (3 N) from the sum of m v^2 over this rank's atoms (the standalone's temperature:
  //! 3N degrees of freedom).
  double temperature_of(double local_mv2) const;
  //! The same from LAMMPS's rows.
  double temperature_now() const;
  //! Gravity, inelastic collisions or rotation (energy moving between translation and rotation)
  //! change the temperature inside the steps: it is measured after every step, so <T> is the
  //! average of the steps' end temperatures, as LAMMPS's press.
  bool temperature_varies() const { return !physics.elastic() || physics.has_gravity() || physics.rough(); }
  //! After another fix's step-end hooks: atoms it moved (compared with what was kept)?
  bool positions_moved() const;
  //! Names the fixes that may have moved atoms at the end of the last step, for an error.
  std::string moved_source() const;
  //! The stepper settings of this fix's keywords and the timestep (both paths use them).
  hardsphere::StepperConfig stepper_config() const;

  // Keywords.
  bool sweep = false;
  bool ghost_auto = true;
  bool ghost_path_only = false;  //!< 'path ghosts': the owned + ghost path in serial too
  std::int64_t max_events = 100000000;
  //! Restitution, contact time, tangential restitution, friction and inertia from the keywords,
  //! gravity from the fix gravity commands (read at setup); validated at setup.
  hardsphere::Physics physics = keyword_defaults();
  static hardsphere::Physics keyword_defaults() {
    hardsphere::Physics p;
    p.contact_time = hardsphere::kDefaultContactTime;
    return p;
  }
  hardsphere::PhysicsGiven given;        //!< the keywords given: one that would have no effect is refused
  std::set<std::string> wall_keys_seen;  //!< 'KEY face' of the wall keywords (each once)
  PartTimer timing;                      //!< 'timing yes': wall time per part, printed at the end of each run

  double dt = 0.0;
  std::unique_ptr<StepPath> path;    //!< made at the first init(): serial on one rank, else owned + ghost
  OtherFixes others;                 //!< when other fixes read or change x and v (init)
  std::vector<Fix *> gravity_fixes;  //!< fix gravity commands, acting through the stepper
  int kinematic_bits = 0;            //!< group bits of fix freeze groups: kinematic spheres (serial path)
  std::vector<double> x_kept;        //!< owned x before other fixes' step-end hooks, if they may move atoms
  bool positions_kept = false;       //!< x_kept was taken in the last step (on every rank alike)
  std::vector<class FixWallHardSphere *> wall_fixes;  //!< fix wall/hardsphere commands: walls of the stepper
  //! fix wall/hardsphere/region commands (their walls follow wall_fixes' in physics.shapes) and
  //! where each one's walls start there.
  std::vector<class FixWallHardSphereRegion *> region_fixes;
  std::vector<std::size_t> region_first;
  std::string walls_at_setup;  //!< their walls as the last setup read them

  // Per-atom collision virial (compute stress/atom): each collision's r_ij (x) dp_i / dt, half to
  // each atom, taken from the stepper right after a step on which LAMMPS asks for it and kept
  // in vstep (a per-atom array that LAMMPS sorts and migrates with the atoms) until post_force.
  bool atom_virial = false;  //!< some compute asks for per-atom virials (set at init)
  double **vstep = nullptr;  //!< 6 per atom, allocated only while atom_virial
  int vstep_rows = 0;        //!< rows allocated
  bigint vstep_at = -1;      //!< the step vstep holds (-1: none)

  // Per-step and cumulative tallies (local, weighted by ownership on the owned + ghost path;
  // compute_vector sums over ranks).
  double step_virial[6] = {0, 0, 0, 0, 0, 0};
  double n_coll = 0, n_coll_step = 0, virial_sum = 0, n_wall = 0, n_global = 0, n_forced = 0, n_unresolved = 0;
  double sim_time = 0.0;
  // Time-averaged temperature for Z and P (f_ID[9], f_ID[10]): collisions keep the kinetic
  // energy, so the temperature is recomputed only when something else may have changed it.
  double t_now = 0.0;                      //!< current temperature, 2 KE / (3 N)
  double t_integral = 0.0;                 //!< sum over steps of t_now * dt (since the fix was defined)
  bool run_set_up = false;                 //!< setup() ran for this run ('run ... pre no' skips it)
  bool initialised = false;                //!< init() ran (a fix defined just before 'run ... pre no' misses it)
  bool in_rerun = false;                   //!< the setup() of a 'rerun' (no stepper) was the last one
  bool after_rerun = false;                //!< the last setup() was a rerun's: LAMMPS holds a snapshot
  bool serial = false;                     //!< the path is the serial one (decided at init)
  std::vector<std::string> fixes_at_init;  //!< IDs of all fixes when check_other_fixes() last ran
  bool neigh_noted = false;                //!< the neighbour settings message was printed
  int newton_saved = -1;                   //!< force->newton before this run, while the fix has turned it off
  bool newton_noted = false;               //!< the reverse-communication message was printed
};

}  // namespace LAMMPS_NS
