// The MPI path's step over owned and ghost atoms: run and step starts, the ghosts' sync, the
// step itself and writing the owned atoms back (the re-run, checks and communication: ghost_*.cpp).
#include "ghost_path.h"

#include <mpi.h>

#include <algorithm>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "neigh_list.h"
#include "neighbor.h"

using namespace LAMMPS_NS;
using hardsphere::Vec3d;

void GhostPath::run_starts() {
  setup_layout_ = box_layout();
  stale_ = epoch_ = check_start_ = true;
  // Lists LAMMPS builds at every re-neighbouring for other styles (the fix and pair style ask for
  // none), e.g. a dynamic group's 'within' (LAMMPS 2026): valid only while no atom has moved half
  // the skin since, which the path's own criterion does not watch.
  other_lists_ = false;
  for (int i = 0; i < neighbor->nlist; i++)
    if (neighbor->lists[i] && !neighbor->lists[i]->occasional) other_lists_ = true;
  build();
  refresh_v_ = true;
}

bool GhostPath::before_step(const StepStart &start) {
  // LAMMPS's communication pattern (which faces are periodic, how far ghosts reach) is set up in
  // a run's setup; commands between runs that change it need that setup on this path.
  if (start.without_setup && box_layout() != setup_layout_)
    error->all(FLERR,
               "fix hardsphere: the box, its boundaries, the neighbour skin or the ghost cutoff changed since the "
               "last run's setup (change_box, boundary, neighbor, comm_modify), which 'run ... pre no' skips; on "
               "more than one rank or with 'path ghosts', start this run with its setup ('run N' without 'pre no')");
  if (start.without_setup)  // 'run ... pre no': commands in between may have changed atoms
    stale_ = check_start_ = unsure_ghosts_ = true;
  else if (start.others_acted)
    refresh_v_ = true;
  if (!start.moved_by.empty()) {
    moved_ = true;
    moved_source_ = start.moved_by;
  }
  return start.without_setup || start.others_acted;
}

double GhostPath::owned_mv2() const {
  double mv2 = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *v = atom->v[i];
    mv2 += atom->rmass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return mv2;
}

StepTotals GhostPath::step(double *virial_rows, double scale) {
  virial_rows_ = virial_rows;
  virial_scale_ = scale;
  if (unsure_ghosts_) {
    // 'run ... pre no': LAMMPS kept its ghosts and send lists from the last run. If commands in
    // between added, deleted or moved atoms between ranks, changed the sub-domains, or moved or
    // sped atoms up beyond the shell's slack, this step runs for all atoms at once and LAMMPS
    // re-neighbours in it. Otherwise the ghosts' positions are taken from their owners again.
    unsure_ghosts_ = false;
    // A shell LAMMPS has made since (every rank knows) is new and starts a new epoch.
    if (layout_changed() || (!epoch_ && shell_used_up())) {
      moved_ = false;  // this step reads every atom from LAMMPS's rows anyway
      return restart_globally("fix hardsphere", kStartHint);
    }
    forward_comm(2);
  }
  if (moved_) {
    // LAMMPS's ghosts still hold the positions from before the move.
    moved_ = false;
    return restart_globally(moved_source_, kMovedAtomsHint);
  }
  timer_.start();
  if (stale_) {
    build();
    timer_.charge(PartTimer::Remake);
  } else if (stepper_) {
    if (refresh_v_) refresh_velocities();
    sync_ghosts();
    timer_.charge(PartTimer::Ghosts);
  }
  refresh_v_ = false;

  // LAMMPS's x and v keep the step's start until the owner check has passed (a re-run starts
  // from them); the owners' new velocities reach the ghosts first.
  StepTotals t;
  if (stepper_)
    advance_held_atoms();
  else
    agree_rebuild(false);  // the other ranks' steppers ask once per step
  int disagree = ghosts_agree() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &disagree, 1, MPI_INT, MPI_MAX, world);
  timer_.charge(PartTimer::Check);

  if (disagree) {
    t = step_globally(false);
    stale_ = true;
    timer_.charge(PartTimer::Rerun);
  } else if (stepper_) {
    t = write_owned_atoms();
  }

  reneighbor_ = t.rerun ? shell_used_up() : shell_maybe_used_up();
  if (!reneighbor_ && other_lists_) reneighbor_ = lists_expired();
  timer_.charge(PartTimer::Moves);
  return t;
}

void GhostPath::refresh_velocities() {
  // Every atom's velocity from LAMMPS, the ghosts' from their owners.
  forward_comm(0);
  if (slots_.stale(*stepper_)) map_slots();
  hardsphere::state_exchange(*stepper_).gather(hardsphere::SphereField::Velocity, slots_.rows(), atom->v[0]);
  double **v = atom->v;
  v_owner_.resize(std::size_t(atom->nlocal + atom->nghost));
  for (const std::uint32_t k : slots_.ghost_slots()) {
    const int g = int(slots_.rows()[k]);
    v_owner_[std::size_t(g)] = {v[g][0], v[g][1], v[g][2]};
  }
  if (physics_.rough()) refresh_omegas();
}

void GhostPath::advance_held_atoms() {
  hardsphere::state_exchange(*stepper_).set_sphere_virial(virial_rows_ != nullptr);
  tally_.start_step();
  try {
    stepper_->run(1);
  } catch (const std::exception &e) {
    error->one(FLERR, std::string("fix hardsphere: ") + e.what());
  }
  timer_.charge(PartTimer::Steps);
  moved_bound_ += stepper_->step_speed_bound() * config_.dt;
  if (slots_.stale(*stepper_)) map_slots();
  sent_vel_.resize(sent_slots_.size());
  hardsphere::state_exchange(*stepper_).copy(hardsphere::SphereField::Velocity, sent_slots_.data(), sent_slots_.size(),
                                             sent_vel_.data());
  if (physics_.rough()) copy_sent_omegas();
}

StepTotals GhostPath::write_owned_atoms() {
  double **x = atom->x, **v = atom->v;
  hardsphere::state_exchange(*stepper_).scatter_state(slots_.owned_rows(), slots_.shifts(), x[0], v[0]);
  if (physics_.rough())
    hardsphere::state_exchange(*stepper_).scatter(hardsphere::SphereField::Omega, slots_.owned_rows(), atom->omega[0]);
  if (virial_rows_) {  // only owned rows: a ghost's share is its owner's
    std::fill(virial_rows_, virial_rows_ + 6 * atom->nlocal, 0.0);
    hardsphere::state_exchange(*stepper_).take_sphere_virial(slots_.owned_rows(), virial_scale_, virial_rows_);
  }
  timer_.charge(PartTimer::Write);
  StepTotals t;
  const OwnershipTally::Totals &c = tally_.totals();
  static_cast<hardsphere::WeightedCollisionTotals &>(t) = c - last_;
  last_ = c;
  const std::int64_t unresolved = stepper_->counters().unresolved_steps;
  t.unresolved = double(unresolved - last_unresolved_);
  last_unresolved_ = unresolved;
  return t;
}

StepTotals GhostPath::restart_globally(const std::string &source, const std::string &hint) {
  timer_.start();
  StepTotals t = step_globally(true, source, hint);
  t.rerun = false;  // not a disagreement
  stale_ = reneighbor_ = true;
  timer_.charge(PartTimer::Rerun);
  return t;
}

bool GhostPath::agree_rebuild(bool due) {
  // Every rank waits for the slowest after each step: one rank's pair-list rebuild would
  // stall all the others, so all rebuild on the steps any of them needs to.
  int any = due ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_LOR, world);
  return any != 0;
}

void GhostPath::map_slots() {
  // Only owned rows are written back: a ghost's row is its owner's, refreshed by LAMMPS.
  slots_.make(*stepper_, input_local_, input_shift_, {}, domain->prd, atom->nlocal);
  sent_slots_.resize(sent_rows_.size());
  for (std::size_t b = 0; b < sent_rows_.size(); b++) sent_slots_[b] = slots_.slot_of_row(sent_rows_[b]);
}

void GhostPath::sync_ghosts() {
  // Each ghost copy starts the step as its owner ended the last one: LAMMPS has refreshed the
  // ghosts' positions, the owner check brought their velocities. Copies then differ only by
  // what one step's collision chains from beyond the shell can do, which the check catches.
  if (slots_.stale(*stepper_)) map_slots();
  double **x = atom->x;
  const std::vector<std::uint32_t> &ghosts = slots_.ghost_slots();
  const std::size_t n = ghosts.size();
  ghost_pos_.resize(n), ghost_vel_.resize(n);
  for (std::size_t i = 0; i < n; i++) {
    const std::uint32_t k = ghosts[i];
    const int g = int(slots_.rows()[k]);
    ghost_pos_[i] = Vec3d{x[g][0], x[g][1], x[g][2]} - slots_.shifts()[k];
    ghost_vel_[i] = v_owner_[std::size_t(g)];
  }
  auto &exch = hardsphere::state_exchange(*stepper_);
  exch.set(hardsphere::SphereField::Position, ghosts.data(), n, ghost_pos_.data());
  exch.set(hardsphere::SphereField::Velocity, ghosts.data(), n, ghost_vel_.data());
  if (physics_.rough()) sync_ghost_omegas();
}

void GhostPath::run_ends() {
  end_atoms_[0] = atom->nlocal, end_atoms_[1] = 0;
  for (int i = 0; i < atom->nlocal; i++) end_atoms_[1] += atom->tag[i];
  for (int d = 0; d < 3; d++)
    end_subdomain_[std::size_t(d)] = domain->sublo[d], end_subdomain_[std::size_t(d + 3)] = domain->subhi[d];
}
