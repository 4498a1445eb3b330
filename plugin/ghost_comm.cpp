// The fix's forward communication on the MPI path: learning LAMMPS's swaps, velocities (and
// positions) packed and unpacked, rough spheres' omegas alongside (GhostPath, ghost_path.h).
#include <mpi.h>

#include <algorithm>
#include <vector>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "ghost_path.h"
#include "lammps_atoms.h"
#include "lammps_compat.h"

using namespace LAMMPS_NS;
using hardsphere::Vec3d;

void GhostPath::forward_comm_learning_swaps() {
  // LAMMPS's send lists and swaps stay as they are until it re-neighbours: learn which owned
  // rows other ranks hold as ghosts and which swaps only copy to this rank itself.
  sent_rows_.clear(), rows_self_.clear(), rows_pending_.clear(), self_swap_.clear();
  self_row_.assign(std::size_t(atom->nlocal + atom->nghost), 0);
  packed_ = nullptr;
  swaps_known_ = true;
  record_sends_ = true;
  forward_comm(0);
  record_sends_ = false;
  if (packed_) swaps_known_ = false;  // a pack without its unpack
  // Velocities after the step go to other ranks only, unless the swaps were not recognised.
  if (!swaps_known_) sent_rows_.insert(sent_rows_.end(), rows_self_.begin(), rows_self_.end());
  std::sort(sent_rows_.begin(), sent_rows_.end());
  sent_rows_.erase(std::unique(sent_rows_.begin(), sent_rows_.end()), sent_rows_.end());
  row_sent_.assign(std::size_t(atom->nlocal), -1);
  for (std::size_t b = 0; b < sent_rows_.size(); b++) row_sent_[std::size_t(sent_rows_[b])] = int(b);
}

void GhostPath::forward_comm(int mode) {
  comm_mode_ = mode;
  swap_ = 0;
  hs_compat::forward_comm(comm, fix_, forward_size(physics_.rough()));
  comm_mode_ = 0;
}

int GhostPath::pack_forward(int n, int *list, double *buf, int pbc_flag, const int *pbc) {
  if (record_sends_) {
    if (packed_) swaps_known_ = false;  // two packs in a row
    packed_ = buf;
    for (int k = 0; k < n; k++)
      if (list[k] < atom->nlocal) rows_pending_.push_back(list[k]);
  }
  if (skip_swap()) return 0;
  double **v = atom->v, **x = atom->x;
  int m = 0;
  if (comm_mode_ == 2) {  // positions, shifted across periodic faces as LAMMPS's own comm does
    const double shift[3] = {pbc_flag ? pbc[0] * domain->xprd : 0.0, pbc_flag ? pbc[1] * domain->yprd : 0.0,
                             pbc_flag ? pbc[2] * domain->zprd : 0.0};
    for (int k = 0; k < n; k++)
      for (int d = 0; d < 3; d++) buf[m++] = x[list[k]][d] + shift[d];
    return m;
  }
  for (int k = 0; k < n; k++) {
    const int j = list[k];
    if (comm_mode_ == 1) {  // after the step: an owner's new velocity, or a ghost's passed on
      const Vec3d &o = j < atom->nlocal ? sent_vel_[std::size_t(row_sent_[std::size_t(j)])] : v_owner_[std::size_t(j)];
      buf[m++] = o.x, buf[m++] = o.y, buf[m++] = o.z;
    } else {
      buf[m++] = v[j][0], buf[m++] = v[j][1], buf[m++] = v[j][2];
    }
    if (physics_.rough()) m = pack_omega(j, buf, m);
  }
  return m;
}

void GhostPath::unpack_forward(int n, int first, double *buf) {
  if (record_sends_) {
    if (!packed_) swaps_known_ = false;  // an unpack without its pack
    const bool self = buf == packed_;
    self_swap_.push_back(self ? 1 : 0);
    if (self) std::fill(self_row_.begin() + first, self_row_.begin() + first + n, std::uint8_t(1));
    auto &rows = self ? rows_self_ : sent_rows_;
    rows.insert(rows.end(), rows_pending_.begin(), rows_pending_.end());
    rows_pending_.clear();
    packed_ = nullptr;
  }
  const bool skip = skip_swap();
  ++swap_;
  if (skip) return;
  double **row = comm_mode_ == 2 ? atom->x : atom->v;
  const bool omegas = comm_mode_ != 2 && physics_.rough();
  for (int i = first, m = 0; i < first + n; i++, m += omegas ? 6 : 3) {
    if (comm_mode_ == 1)  // owners' results, kept apart from this rank's copies
      v_owner_[std::size_t(i)] = {buf[m], buf[m + 1], buf[m + 2]};
    else
      row[i][0] = buf[m], row[i][1] = buf[m + 1], row[i][2] = buf[m + 2];
    if (omegas) unpack_omega(i, buf + m + 3);
  }
}

// Rough spheres: angular velocities travel with the velocities (LAMMPS's omega rows, the owners'
// results in w_owner_), in the same communications and checks.

Vec3d GhostPath::omega_of(int i) const {
  if (!physics_.rough()) return {0, 0, 0};
  const double *w = atom->omega[i];
  return {w[0], w[1], w[2]};
}

void GhostPath::sync_ghost_omegas() {
  const std::vector<std::uint32_t> &ghosts = slots_.ghost_slots();
  ghost_w_.resize(ghosts.size());
  for (std::size_t i = 0; i < ghosts.size(); i++) ghost_w_[i] = w_owner_[slots_.rows()[ghosts[i]]];
  hardsphere::state_exchange(*stepper_).set(hardsphere::SphereField::Omega, ghosts.data(), ghosts.size(),
                                            ghost_w_.data());
}

void GhostPath::refresh_omegas() {
  hardsphere::state_exchange(*stepper_).gather(hardsphere::SphereField::Omega, slots_.rows(), atom->omega[0]);
  w_owner_.resize(std::size_t(atom->nlocal + atom->nghost));
  for (const std::uint32_t k : slots_.ghost_slots()) w_owner_[slots_.rows()[k]] = omega_of(int(slots_.rows()[k]));
}

void GhostPath::copy_sent_omegas() {
  sent_w_.resize(sent_slots_.size());
  hardsphere::state_exchange(*stepper_).copy(hardsphere::SphereField::Omega, sent_slots_.data(), sent_slots_.size(),
                                             sent_w_.data());
}

int GhostPath::pack_omega(int j, double *buf, int m) const {
  const Vec3d w = comm_mode_ == 1
                      ? (j < atom->nlocal ? sent_w_[std::size_t(row_sent_[std::size_t(j)])] : w_owner_[std::size_t(j)])
                      : omega_of(j);
  buf[m++] = w.x, buf[m++] = w.y, buf[m++] = w.z;
  return m;
}

void GhostPath::unpack_omega(int i, const double *buf) {
  if (comm_mode_ == 1)
    w_owner_[std::size_t(i)] = {buf[0], buf[1], buf[2]};
  else
    atom->omega[i][0] = buf[0], atom->omega[i][1] = buf[1], atom->omega[i][2] = buf[2];
}
