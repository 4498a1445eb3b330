// The MPI path's checks: the owner check of the ghosts' velocities (and omegas), a changed layout
// between runs, and when LAMMPS must re-neighbour (GhostPath, ghost_path.h).
#include <mpi.h>

#include <cmath>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "ghost_path.h"
#include "neighbor.h"

using namespace LAMMPS_NS;
using hardsphere::Vec3d;

bool GhostPath::ghosts_agree() {
  // A ghost copy evolves from what this rank sees around it. An owned atom's step is right if
  // every ghost it met was right; each such ghost must end the step with its owner's velocity
  // (rounding differs between copies by ~1e-15). The owners' velocities also start the ghost
  // copies' next step (sync_ghosts).
  const int nall = atom->nlocal + atom->nghost;
  v_owner_.resize(std::size_t(nall));
  if (physics_.rough()) w_owner_.resize(std::size_t(nall));
  forward_comm(1);
  if (!stepper_) return true;
  auto &exch = hardsphere::state_exchange(*stepper_);
  met_slots_.clear();
  for (const std::uint32_t k : slots_.ghost_slots())
    if (tally_.met_owned(k)) met_slots_.push_back(k);
  met_vel_.resize(met_slots_.size());
  exch.copy(hardsphere::SphereField::Velocity, met_slots_.data(), met_slots_.size(), met_vel_.data());
  for (std::size_t i = 0; i < met_slots_.size(); i++) {
    const Vec3d &owner = v_owner_[slots_.rows()[met_slots_[i]]];
    if (!(std::sqrt(norm2(met_vel_[i] - owner)) <= 1e-9 * (1.0 + std::sqrt(norm2(owner))))) return false;
  }
  return !physics_.rough() || omegas_agree();
}

bool GhostPath::omegas_agree() {
  // As the velocities: the contact points' speeds a w, against the owner's to 1e-9.
  met_w_.resize(met_slots_.size());
  hardsphere::state_exchange(*stepper_).copy(hardsphere::SphereField::Omega, met_slots_.data(), met_slots_.size(),
                                             met_w_.data());
  for (std::size_t i = 0; i < met_slots_.size(); i++) {
    const std::uint32_t row = slots_.rows()[met_slots_[i]];
    const Vec3d &owner = w_owner_[row];
    const double a = atom->radius[row];
    if (!(a * std::sqrt(norm2(met_w_[i] - owner)) <= 1e-9 * (1.0 + a * std::sqrt(norm2(owner))))) return false;
  }
  return true;
}

std::vector<double> GhostPath::box_layout() const {
  std::vector<double> l(14);
  for (int d = 0; d < 3; d++) {
    l[std::size_t(4 * d)] = domain->boxlo[d], l[std::size_t(4 * d + 1)] = domain->boxhi[d];
    l[std::size_t(4 * d + 2)] = double(domain->periodicity[d]), l[std::size_t(4 * d + 3)] = comm->cutghost[d];
  }
  l[12] = neighbor->skin, l[13] = comm->cutghostuser;
  return l;
}

bool GhostPath::layout_changed() const {
  bigint sum = 0;
  for (int i = 0; i < atom->nlocal; i++) sum += atom->tag[i];
  int changed = atom->nlocal != end_atoms_[0] || sum != end_atoms_[1] ? 1 : 0;
  for (int d = 0; d < 3; d++)  // change_box, balance
    if (domain->sublo[d] != end_subdomain_[std::size_t(d)] || domain->subhi[d] != end_subdomain_[std::size_t(d + 3)])
      changed = 1;
  MPI_Allreduce(MPI_IN_PLACE, &changed, 1, MPI_INT, MPI_MAX, world);
  return changed != 0;
}

bool GhostPath::shell_maybe_used_up() {
  // The steppers' speed bounds bound every move: the exact test, a pass over the owned atoms,
  // runs only once the bound could reach the slack (it decides as the exact test alone would).
  const double speed = stepper_ ? stepper_->step_speed_bound() : 0.0;
  int maybe = 2.0 * (moved_bound_ + 2.0 * speed * config_.dt) >= reach_ ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &maybe, 1, MPI_INT, MPI_LOR, world);
  return maybe && shell_used_up();
}

bool GhostPath::shell_used_up() {
  // Largest owned move since the epoch began, from LAMMPS's rows. Before the next step every
  // atom that can meet an owned atom must be here: the shell is used up when the moves (both
  // atoms of a pair) and one more step could exceed its slack.
  double moves[2] = {0, 0};
  double **x = atom->x, **v = atom->v;
  for (int i = 0; i < atom->nlocal; i++) {
    moves[0] = std::max(moves[0], norm2(Vec3d{x[i][0], x[i][1], x[i][2]} - x_ref_[std::size_t(i)]));
    moves[1] = std::max(moves[1], norm2(Vec3d{v[i][0], v[i][1], v[i][2]}));
  }
  MPI_Allreduce(MPI_IN_PLACE, moves, 2, MPI_DOUBLE, MPI_MAX, world);
  moved_bound_ = std::sqrt(moves[0]);
  return 2.0 * (std::sqrt(moves[0]) + 2.0 * std::sqrt(moves[1]) * config_.dt) >= reach_;
}

bool GhostPath::lists_expired() {
  // LAMMPS's own rule for its lists (neigh_modify check yes): re-neighbour once an atom has moved
  // more than half the skin since the last build. The moves' bound decides first, as above.
  const double half_skin = 0.5 * neighbor->skin;
  int maybe = moved_bound_ > half_skin ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &maybe, 1, MPI_INT, MPI_LOR, world);
  if (!maybe) return false;
  double move2 = 0;
  double **x = atom->x;
  for (int i = 0; i < atom->nlocal; i++)
    move2 = std::max(move2, norm2(Vec3d{x[i][0], x[i][1], x[i][2]} - x_ref_[std::size_t(i)]));
  MPI_Allreduce(MPI_IN_PLACE, &move2, 1, MPI_DOUBLE, MPI_MAX, world);
  moved_bound_ = std::sqrt(move2);
  return move2 > half_skin * half_skin;
}
