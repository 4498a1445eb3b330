#pragma once
//! The MPI path of fix hardsphere: on each rank one standalone stepper over the rank's owned
//! atoms and the ghost atoms LAMMPS provides around its sub-domain (a periodic axis the
//! sub-domain spans keeps its period; LAMMPS's images along it are left out). LAMMPS decomposes the box,
//! migrates atoms and makes new ghosts when this class asks it to re-neighbour; in between, each
//! rank's copies of its ghosts start every step as their owners ended the last one. Every ghost
//! that met an owned atom in a step must end it like its owner; if one does not (a collision
//! chain ran in from beyond the ghost shell), the step is re-run for all atoms at once.
//! Collision totals are weighted by ownership, so the ranks add up to one stepper's totals.
//! Its parts: ghost_path.cpp (the step), ghost_build.cpp (the rank's stepper), ghost_rerun.cpp
//! (the re-run for all atoms), ghost_checks.cpp (owner check, re-neighbouring), ghost_comm.cpp.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hardsphere/state_exchange.hpp"
#include "hardsphere/stepper.hpp"
#include "ownership_tally.h"
#include "part_timer.h"
#include "pointers.h"
#include "slot_map.h"
#include "step_path.h"

namespace LAMMPS_NS {

class GhostPath : public StepPath, protected Pointers {
 public:
  GhostPath(LAMMPS *lmp, class Fix *fix, PartTimer &timer) : Pointers(lmp), fix_(fix), timer_(timer) {}
  //! noexcept as StepPath's: newer LAMMPS declares ~Pointers() noexcept(false).
  ~GhostPath() noexcept override = default;
  void configure(const hardsphere::StepperConfig &c, const hardsphere::Physics &p) override {
    config_ = c;
    physics_ = p;
  }
  //! The ghost shell for contact distance `contact` and LAMMPS's skin: a ghost an owned atom
  //! meets must see all its own partners (two contact distances), and the skin twice over plus
  //! one more contact distance is what atoms may move before LAMMPS re-neighbours.
  static double ghost_cutoff(double contact, double skin) { return 3.0 * contact + 2.0 * skin; }
  void set_gravity(const std::array<double, 3> &g) override {
    physics_.gravity = g;
    if (stepper_) stepper_->set_gravity(g);
  }
  void set_shape_rotation(std::size_t k, double omega) override {
    physics_.shapes.at(k).omega = omega;
    if (stepper_) stepper_->set_shape_rotation(k, omega);
  }
  //! New ghosts, atoms may have changed ranks: the stepper is made again before the next step.
  void neighbours_changed() override { stale_ = epoch_ = true; }
  //! The stepper is made now (outside the run's loop, as the serial path's is) from LAMMPS's
  //! atoms and checked as a run's start; the first step still takes up velocities that other
  //! fixes' setup may have changed.
  void run_starts() override;
  bool before_step(const StepStart &start) override;
  //! Advances the owned atoms (and this rank's ghost copies) by one step.
  StepTotals step(double *virial_rows, double scale) override;
  double owned_mv2() const override;
  //! Whether LAMMPS must re-neighbour before the next step so that every atom an owned atom
  //! can meet is among this rank's ghosts.
  bool needs_reneighbor() const override { return reneighbor_; }
  //! A run ends: the owned atoms, against which the next run without setup compares.
  void run_ends() override;
  int pack_forward(int n, int *list, double *buf, int pbc_flag, const int *pbc) override;
  void unpack_forward(int n, int first, double *buf) override;

 private:
  void build();
  //! A run's start: the owned atoms as the serial path checks them (error->one naming the atom),
  //! and the run's overlap tolerance.
  void check_owned_atoms();
  //! The rank's box: the bounds of the held atoms along each axis, and which axes it spans whole.
  struct RankBox {
    hardsphere::Box box;
    std::array<bool, 3> whole{};
    double lo[3], hi[3];  //!< the ghost shell's bounds (ghosts beyond them are not held)
  };
  //! build()'s steps: the rank's box (and which walls its stepper never reaches), the owned atoms
  //! and the ghosts it holds (owned: per input, whether it is owned), the start's overlap check,
  //! and the stepper with its ownership tally.
  RankBox rank_box(double shell, double dmax, hardsphere::StepperConfig &config) const;
  hardsphere::ParticleSystem held_atoms(const RankBox &b, double dmax, std::vector<std::uint8_t> &owned);
  void check_held_overlaps(const hardsphere::ParticleSystem &sys);
  void make_rank_stepper(const hardsphere::ParticleSystem &sys, const hardsphere::StepperConfig &config,
                         const std::vector<std::uint8_t> &owned);
  void start_epoch(double shell, double dmax);
  void map_slots();
  //! step()'s parts: LAMMPS's velocities taken up (another fix changed them), the stepper's step
  //! (the velocities other ranks hold as ghosts kept for the owner check), and once the check
  //! has passed, the owned atoms written back with this step's totals.
  void refresh_velocities();
  void advance_held_atoms();
  StepTotals write_owned_atoms();
  void sync_ghosts();
  void forward_comm(int mode);
  void forward_comm_learning_swaps();
  bool skip_swap() const { return comm_mode_ == 1 && swaps_known_ && swap_ < self_swap_.size() && self_swap_[swap_]; }
  bool agree_rebuild(bool due);
  bool ghosts_agree();
  //! One step for all atoms at once from LAMMPS's rows; `check` refuses an invalid start
  //! (overlaps, atoms outside fixed walls), naming `source` and what to do.
  StepTotals step_globally(bool check, const std::string &source = "fix hardsphere",
                           const std::string &hint = kStartHint);
  //! This step for all atoms at once, with the start checked, and LAMMPS re-neighbouring in it.
  StepTotals restart_globally(const std::string &source, const std::string &hint);
  //! From an engine over all atoms (step_globally): the owned atoms' collision virials.
  void take_owned_virial(hardsphere::StateExchange &exch);
  // Rough spheres' angular velocities, alongside the velocities (ghost_comm.cpp's last part).
  hardsphere::Vec3d omega_of(int row) const;  //!< LAMMPS's omega row (zero for smooth spheres)
  void sync_ghost_omegas();                   //!< the ghost copies' omegas from their owners
  void refresh_omegas();                      //!< every omega from LAMMPS's rows
  void copy_sent_omegas();                    //!< the omegas of the owned atoms others hold as ghosts
  bool omegas_agree();                        //!< the owner check of the ghosts' omegas
  int pack_omega(int row, double *buf, int m) const;
  void unpack_omega(int row, const double *buf);
  //! The box, its periodicity, LAMMPS's ghost cutoffs and skin: what a run's setup fixes.
  std::vector<double> box_layout() const;
  //! Whether any rank's owned atoms or sub-domain differ from those at the end of the last run.
  bool layout_changed() const;
  //! Whether the moves since the epoch began could let an atom that is not held reach an owned
  //! atom's partners within the next step (all ranks agree).
  bool shell_used_up();
  //! The same, decided by the steppers' speed bounds while those keep every move short of the
  //! slack: the exact pass over the owned atoms only near the end of an epoch.
  bool shell_maybe_used_up();
  //! Whether other styles' LAMMPS lists (other_lists_) need re-neighbouring: an atom moved more
  //! than half the skin since the last one (all ranks agree).
  bool lists_expired();
  static double norm2(const hardsphere::Vec3d &a) { return a.x * a.x + a.y * a.y + a.z * a.z; }

  class Fix *fix_;
  PartTimer &timer_;
  hardsphere::StepperConfig config_;  //!< for every stepper this path makes
  hardsphere::Physics physics_;
  bool stale_ = true, epoch_ = true, refresh_v_ = false, reneighbor_ = false, check_start_ = true;
  bool unsure_ghosts_ = false;
  bigint atoms_built_ = -1;              //!< atom->natoms when the steppers were last made
  const char *check_hint_ = kStartHint;  //!< what the start checks tell the user (a run's start, an insertion)
  double overlap_slack_ = 0;             //!< overlaps up to this are the stepper's rounding (check_owned_atoms)
  bool moved_ = false;                   //!< see atoms_moved()
  std::string moved_source_;             //!< the fix that moved them, for an error message
  double *virial_rows_ = nullptr;        //!< this step's per-atom virial rows (see step())
  double virial_scale_ = 1.0;
  std::vector<double> setup_layout_;       //!< box_layout() at the last run's setup
  bigint end_atoms_[2] = {-1, -1};         //!< owned atoms and the sum of their tags when the last run ended
  std::array<double, 6> end_subdomain_{};  //!< and the sub-domain's bounds
  OwnershipTally tally_;                   //!< the stepper's collisions weighted by ownership
  std::unique_ptr<hardsphere::StepperBase> stepper_;
  OwnershipTally::Totals last_;  //!< tally_ after the previous step
  std::int64_t last_unresolved_ = 0;
  std::vector<int> input_local_;                //!< stepper input index -> LAMMPS local index
  std::vector<hardsphere::Vec3d> input_shift_;  //!< LAMMPS x - stepper position at build, per input
  SlotMap slots_;
  std::vector<hardsphere::Vec3d> ghost_pos_, ghost_vel_;  //!< scratch for sync_ghosts
  std::vector<std::uint32_t> met_slots_;                  //!< those slots
  std::vector<hardsphere::Vec3d> met_vel_;                //!< and this rank's velocities of them
  std::vector<hardsphere::Vec3d> x_ref_;                  //!< owned positions when LAMMPS last re-neighboured
  std::vector<hardsphere::Vec3d> v_owner_;                //!< per ghost: its owner's velocity after the step
  std::vector<hardsphere::Vec3d> w_owner_, sent_w_, met_w_, ghost_w_;  //!< the same for rough spheres' omegas
  // Owned atoms that other ranks hold as ghosts (and this rank's own periodic images, if the
  // swaps were not recognised): LAMMPS's rows, recorded from its send lists at the build, their
  // slots, and their velocities after the step, sent before LAMMPS's own rows are written.
  std::vector<int> sent_rows_;
  std::vector<std::uint32_t> sent_slots_;
  std::vector<hardsphere::Vec3d> sent_vel_;
  std::vector<int> row_sent_;  //!< per owned row: its index in sent_rows_, or -1
  bool record_sends_ = false;
  // LAMMPS's forward communication, swap by swap in call order: which swaps copy atoms to this
  // rank itself (periodic images along an unsplit axis, which no rank's stepper uses). The
  // owner check skips them when the pattern was recognised (each pack followed by its unpack).
  std::vector<std::uint8_t> self_swap_;
  std::vector<std::uint8_t> self_row_;         //!< per LAMMPS row: a ghost a self swap made
  std::vector<int> rows_pending_, rows_self_;  //!< while recording: rows of the current swap, of self swaps
  const double *packed_ = nullptr;             //!< the last pack's buffer (a self swap unpacks from it)
  std::size_t swap_ = 0;                       //!< swaps so far in the current communication
  bool swaps_known_ = false;
  int comm_mode_ = 0;         //!< 0: velocities, 1: owners' results, 2: positions
  double reach_ = 0;          //!< slack of the ghost shell when LAMMPS last re-neighboured (length)
  double moved_bound_ = 0;    //!< bound of every owned atom's move since the epoch began
  bool other_lists_ = false;  //!< LAMMPS builds lists for other styles at re-neighbourings (run_starts)
};

}  // namespace LAMMPS_NS
