// Making a rank's stepper over its owned atoms and the ghosts within the shell, the run's
// start checks, and the epoch a shell lasts (GhostPath, ghost_path.h).
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "ghost_path.h"
#include "hardsphere/errors.hpp"
#include "hardsphere/particles.hpp"
#include "lammps_atoms.h"

using namespace LAMMPS_NS;
using hardsphere::Vec3d;

namespace {

// How far p lies outside the box [lo, hi] (0 inside).
double distance_outside(const double *p, const double *lo, const double *hi) {
  double s = 0;
  for (int d = 0; d < 3; d++) {
    const double e = std::max({lo[d] - p[d], p[d] - hi[d], 0.0});
    s += e * e;
  }
  return std::sqrt(s);
}

}  // namespace

void GhostPath::check_owned_atoms() {
  // The serial path's checks in LAMMPS's box (walls, finite and resolvable numbers, overlaps
  // among owned atoms), before any of them is wrapped into this rank's box.
  AtomRows rows;
  rows.rough = physics_.rough();
  hardsphere::ParticleSystem sys = atoms_to_system(atom, lammps_box(domain), rows);
  // Overlaps are checked in build(), over owned and ghost atoms, with the tolerance the serial
  // path uses: overlap_tolerance() of the whole state, the largest of the ranks' (it grows with
  // the largest radius; the box is the same).
  const double eps = hardsphere::rounding_epsilon(hardsphere::Precision::Double);
  try {
    hardsphere::validate_and_wrap(sys, "fix hardsphere", nullptr, eps, false);
  } catch (const std::exception &e) {
    error->one(FLERR, std::string(e.what()) + "; " + check_hint_);
  }
  overlap_slack_ = hardsphere::overlap_tolerance(sys, eps);
  MPI_Allreduce(MPI_IN_PLACE, &overlap_slack_, 1, MPI_DOUBLE, MPI_MAX, world);
}

void GhostPath::build() {
  // A fix inserted or deleted atoms (fix pour, deposit, evaporate): the new set is checked as a
  // run's start is.
  if (atoms_built_ >= 0 && atom->natoms != atoms_built_ && !check_start_) {
    check_start_ = true;
    check_hint_ = kInsertedAtomsHint;
  }
  atoms_built_ = atom->natoms;
  if (check_start_) check_owned_atoms();
  // Ghost velocities come from their owners; LAMMPS refreshed the ghost positions.
  forward_comm_learning_swaps();

  double rmax = 0, volume = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double r = atom->radius[i];
    rmax = std::max(rmax, r), volume += r * r * r;
  }
  MPI_Allreduce(MPI_IN_PLACE, &rmax, 1, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(MPI_IN_PLACE, &volume, 1, MPI_DOUBLE, MPI_SUM, world);
  // The rank's box has empty margins: its stepper is tuned by the whole gas's packing fraction.
  hardsphere::StepperConfig config = config_;
  config.packing_fraction = 4.0 / 3.0 * M_PI * volume / (domain->xprd * domain->yprd * domain->zprd);
  const double dmax = 2 * rmax;
  const double shell = std::min({comm->cutghost[0], comm->cutghost[1], comm->cutghost[2]});

  const RankBox b = rank_box(shell, dmax, config);
  std::vector<std::uint8_t> owned;
  const hardsphere::ParticleSystem sys = held_atoms(b, dmax, owned);
  if (check_start_) {
    check_held_overlaps(sys);
    check_start_ = false;
    check_hint_ = kStartHint;
  }
  if (epoch_) start_epoch(shell, dmax);

  stepper_.reset();
  sent_slots_.clear();
  if (!sys.size()) {
    stale_ = false;
    return;
  }
  make_rank_stepper(sys, config, owned);
  map_slots();
  stale_ = false;
}

GhostPath::RankBox GhostPath::rank_box(double shell, double dmax, hardsphere::StepperConfig &config) const {
  // The rank's box: a periodic axis the sub-domain spans keeps its period (LAMMPS's images
  // of it are left out); any other axis ends at the real walls of the box or, inside it, at
  // walls no ghost reaches before LAMMPS re-neighbours (it starts within the shell and moves
  // less than half the shell's slack).
  RankBox b;
  for (int d = 0; d < 3; d++) {
    const bool periodic = domain->periodicity[d] != 0;
    // LAMMPS sets a sub-domain's bounds to the box's exactly where it spans the axis, with brick
    // and tiled (balance rcb) layouts alike; procgrid describes only the brick layout.
    b.whole[std::size_t(d)] = periodic && domain->sublo[d] == domain->boxlo[d] && domain->subhi[d] == domain->boxhi[d];
    b.lo[d] = domain->sublo[d] - shell, b.hi[d] = domain->subhi[d] + shell;
    if (b.whole[std::size_t(d)]) {
      b.box.lo[d] = domain->boxlo[d], b.box.hi[d] = domain->boxhi[d];
    } else {
      const double margin = 1.5 * shell + 2 * dmax;
      const bool wall_lo = !periodic && domain->sublo[d] == domain->boxlo[d];
      const bool wall_hi = !periodic && domain->subhi[d] == domain->boxhi[d];
      b.box.lo[d] = wall_lo ? domain->boxlo[d] : domain->sublo[d] - margin;
      b.box.hi[d] = wall_hi ? domain->boxhi[d] : domain->subhi[d] + margin;
      // Walls in the margin are never reached before the next re-neighbouring: no wall tests.
      config.unreached_walls[std::size_t(d)] = !wall_lo && !wall_hi;
    }
    b.box.periodic[d] = b.whole[std::size_t(d)];
  }
  return b;
}

hardsphere::ParticleSystem GhostPath::held_atoms(const RankBox &b, double dmax, std::vector<std::uint8_t> &owned) {
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  double **x = atom->x;
  // Owned atoms, then the ghosts within the shell that are not periodic images along a whole
  // axis. Ids are tags (the stepper breaks ties by id); a second copy of one atom (possible
  // in boxes a few shells wide) gets an id past every tag.
  tagint max_tag = 0;
  for (int i = 0; i < nall; i++) max_tag = std::max(max_tag, atom->tag[i]);
  std::vector<int> first_copy(std::size_t(max_tag) + 1, -1), next_copy;  // held copies of each tag
  owned.reserve(std::size_t(nall));
  input_local_.clear();
  input_shift_.clear();
  std::int64_t extra_id = std::int64_t(max_tag) + 1;
  AtomRows rows;
  rows.ghosts = true;
  rows.rough = physics_.rough();
  rows.place = [&](int i, const hardsphere::ParticleSystem &held, Vec3d &p, std::int64_t &id) {
    if (i >= nlocal) {
      // This rank's own periodic images miss the owner check's velocities (it skips those
      // swaps): the copy they repeat is held anyway.
      bool keep = !(swaps_known_ && self_row_[std::size_t(i)]);
      for (int d = 0; d < 3 && keep; d++)
        if (!b.whole[std::size_t(d)]) keep = x[i][d] >= b.lo[d] && x[i][d] <= b.hi[d];
      if (!keep) return false;
    }
    for (int d = 0; d < 3; d++)
      if (b.whole[std::size_t(d)]) {
        const double len = domain->prd[d];
        p[d] -= len * std::floor((p[d] - domain->boxlo[d]) / len);
        if (p[d] >= domain->boxhi[d]) p[d] -= len;
      }
    // Along a whole axis the copies of one atom (LAMMPS's images, shifted by the box length)
    // wrap to one position: the first is kept. Copies along split axes lie a box length apart.
    const tagint tag = atom->tag[i];
    bool same = false;
    for (int k = first_copy[std::size_t(tag)]; k >= 0 && !same; k = next_copy[std::size_t(k)])
      same = norm2(held.pos[std::size_t(k)] - p) < 0.25 * dmax * dmax;
    if (same) return false;
    const int copies = first_copy[std::size_t(tag)];
    id = copies >= 0 ? extra_id++ : std::int64_t(tag);
    next_copy.push_back(copies);
    first_copy[std::size_t(tag)] = int(held.size());
    owned.push_back(i < nlocal ? 1 : 0);
    input_local_.push_back(i);
    input_shift_.push_back(Vec3d{x[i][0], x[i][1], x[i][2]} - p);
    return true;
  };
  return atoms_to_system(atom, b.box, rows);
}

void GhostPath::check_held_overlaps(const hardsphere::ParticleSystem &sys) {
  // A run's start, as the serial path checks it: each rank checks the atoms it holds (every
  // pair with an owned atom is held by its owner), naming LAMMPS's tags.
  if (const auto o = hardsphere::find_overlap(sys, overlap_slack_)) {
    std::ostringstream m;
    m.precision(17);
    m << "fix hardsphere: atom " << atom->tag[input_local_[o->i]] << " overlaps atom " << atom->tag[input_local_[o->j]]
      << ": distance " << o->distance << " < contact distance " << o->contact << "; " << check_hint_;
    error->one(FLERR, m.str());
  }
}

void GhostPath::make_rank_stepper(const hardsphere::ParticleSystem &sys, const hardsphere::StepperConfig &config,
                                  const std::vector<std::uint8_t> &owned) {
  try {
    stepper_ = hardsphere::make_stepper(sys, physics_, config);
  } catch (const std::exception &e) {
    error->one(FLERR, std::string("fix hardsphere: ") + e.what());
  }
  auto &exch = hardsphere::state_exchange(*stepper_);
  std::vector<std::uint32_t> input(exch.size());
  exch.copy_input_index(input.data());
  std::vector<std::uint8_t> owned_by_slot(input.size());
  for (std::size_t k = 0; k < input.size(); k++) owned_by_slot[k] = owned[input[k]];
  tally_.reset(std::move(owned_by_slot));
  exch.set_collision_observer(&tally_);
  exch.set_rebuild_agreement([this](bool due) { return agree_rebuild(due); });
  last_ = OwnershipTally::Totals{};
  last_unresolved_ = 0;
}

void GhostPath::start_epoch(double shell, double dmax) {
  // Slack of the shell: a ghost that meets an owned atom (at most `outside` beyond the
  // sub-domain) is within one contact distance of it, and its own partners within another;
  // an atom that is not a ghost was at least `shell` from the sub-domain. The copies of the
  // ghosts an owned atom meets stay complete until the moves of two atoms close the rest.
  const int nlocal = atom->nlocal;
  double **x = atom->x;
  x_ref_.resize(std::size_t(nlocal));
  double outside = 0;
  for (int i = 0; i < nlocal; i++) {
    x_ref_[std::size_t(i)] = {x[i][0], x[i][1], x[i][2]};
    outside = std::max(outside, distance_outside(x[i], domain->sublo, domain->subhi));
  }
  moved_bound_ = 0;
  reach_ = shell - 2 * dmax - outside;
  MPI_Allreduce(MPI_IN_PLACE, &reach_, 1, MPI_DOUBLE, MPI_MIN, world);
  if (!(reach_ > 0))
    error->all(FLERR, "fix hardsphere: the ghost shell (" + std::to_string(shell) +
                          ") does not exceed twice the largest contact distance (" + std::to_string(dmax) +
                          "); raise it with 'comm_modify cutoff'");
  epoch_ = false;
}
