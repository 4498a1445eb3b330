#include "ghost_path.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "hardsphere/errors.hpp"
#include "hardsphere/particles.hpp"
#include "lammps_atoms.h"
#include "lammps_compat.h"
#include "neigh_list.h"
#include "neighbor.h"

using namespace LAMMPS_NS;
using hardsphere::Vec3d;

namespace {

double norm2(const Vec3d &a) { return a.x * a.x + a.y * a.y + a.z * a.z; }

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
    error->one(FLERR, std::string(e.what()) + "; " + kStartHint);
  }
  overlap_slack_ = hardsphere::overlap_tolerance(sys, eps);
  MPI_Allreduce(MPI_IN_PLACE, &overlap_slack_, 1, MPI_DOUBLE, MPI_MAX, world);
}

void GhostPath::build() {
  if (check_start_) check_owned_atoms();
  // Ghost velocities come from their owners; LAMMPS refreshed the ghost positions.
  forward_comm_learning_swaps();

  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  double **x = atom->x;
  double rmax = 0, volume = 0;
  for (int i = 0; i < nlocal; i++) {
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

  // The rank's box: a periodic axis the sub-domain spans keeps its period (LAMMPS's images
  // of it are left out); any other axis ends at the real walls of the box or, inside it, at
  // walls no ghost reaches before LAMMPS re-neighbours (it starts within the shell and moves
  // less than half the shell's slack).
  hardsphere::Box box;
  std::array<bool, 3> whole{};
  double lo[3], hi[3];
  for (int d = 0; d < 3; d++) {
    const bool periodic = domain->periodicity[d] != 0;
    // LAMMPS sets a sub-domain's bounds to the box's exactly where it spans the axis, with brick
    // and tiled (balance rcb) layouts alike; procgrid describes only the brick layout.
    whole[std::size_t(d)] = periodic && domain->sublo[d] == domain->boxlo[d] && domain->subhi[d] == domain->boxhi[d];
    lo[d] = domain->sublo[d] - shell, hi[d] = domain->subhi[d] + shell;
    if (whole[std::size_t(d)]) {
      box.lo[d] = domain->boxlo[d], box.hi[d] = domain->boxhi[d];
    } else {
      const double margin = 1.5 * shell + 2 * dmax;
      const bool wall_lo = !periodic && domain->sublo[d] == domain->boxlo[d];
      const bool wall_hi = !periodic && domain->subhi[d] == domain->boxhi[d];
      box.lo[d] = wall_lo ? domain->boxlo[d] : domain->sublo[d] - margin;
      box.hi[d] = wall_hi ? domain->boxhi[d] : domain->subhi[d] + margin;
      // Walls in the margin are never reached before the next re-neighbouring: no wall tests.
      config.unreached_walls[std::size_t(d)] = !wall_lo && !wall_hi;
    }
    box.periodic[d] = whole[std::size_t(d)];
  }

  // Owned atoms, then the ghosts within the shell that are not periodic images along a whole
  // axis. Ids are tags (the stepper breaks ties by id); a second copy of one atom (possible
  // in boxes a few shells wide) gets an id past every tag.
  tagint max_tag = 0;
  for (int i = 0; i < nall; i++) max_tag = std::max(max_tag, atom->tag[i]);
  std::vector<int> first_copy(std::size_t(max_tag) + 1, -1), next_copy;  // held copies of each tag
  std::vector<std::uint8_t> owned;
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
        if (!whole[std::size_t(d)]) keep = x[i][d] >= lo[d] && x[i][d] <= hi[d];
      if (!keep) return false;
    }
    for (int d = 0; d < 3; d++)
      if (whole[std::size_t(d)]) {
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
  const hardsphere::ParticleSystem sys = atoms_to_system(atom, box, rows);

  if (check_start_) {
    // A run's start, as the serial path checks it: each rank checks the atoms it holds (every
    // pair with an owned atom is held by its owner), naming LAMMPS's tags.
    if (const auto o = hardsphere::find_overlap(sys, overlap_slack_)) {
      std::ostringstream m;
      m.precision(17);
      m << "fix hardsphere: atom " << atom->tag[input_local_[o->i]] << " overlaps atom "
        << atom->tag[input_local_[o->j]] << ": distance " << o->distance << " < contact distance " << o->contact << "; "
        << kStartHint;
      error->one(FLERR, m.str());
    }
    check_start_ = false;
  }
  if (epoch_) start_epoch(shell, dmax);

  stepper_.reset();
  sent_slots_.clear();
  if (!sys.size()) {
    stale_ = false;
    return;
  }
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
  map_slots();
  stale_ = false;
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

std::vector<double> GhostPath::box_layout() const {
  std::vector<double> l(14);
  for (int d = 0; d < 3; d++) {
    l[std::size_t(4 * d)] = domain->boxlo[d], l[std::size_t(4 * d + 1)] = domain->boxhi[d];
    l[std::size_t(4 * d + 2)] = double(domain->periodicity[d]), l[std::size_t(4 * d + 3)] = comm->cutghost[d];
  }
  l[12] = neighbor->skin, l[13] = comm->cutghostuser;
  return l;
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
    if (refresh_v_) {  // every atom's velocity from LAMMPS, the ghosts' from their owners
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
    sync_ghosts();
    timer_.charge(PartTimer::Ghosts);
  }
  refresh_v_ = false;

  // LAMMPS's x and v keep the step's start until the owner check has passed (a re-run starts
  // from them); the owners' new velocities reach the ghosts first.
  StepTotals t;
  if (stepper_) {
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
    hardsphere::state_exchange(*stepper_).copy(hardsphere::SphereField::Velocity, sent_slots_.data(),
                                               sent_slots_.size(), sent_vel_.data());
    if (physics_.rough()) copy_sent_omegas();
  } else {
    agree_rebuild(false);  // the other ranks' steppers ask once per step
  }
  int disagree = ghosts_agree() ? 0 : 1;
  MPI_Allreduce(MPI_IN_PLACE, &disagree, 1, MPI_INT, MPI_MAX, world);
  timer_.charge(PartTimer::Check);

  double **x = atom->x, **v = atom->v;
  if (disagree) {
    t = step_globally(false);
    stale_ = true;
    timer_.charge(PartTimer::Rerun);
  } else if (stepper_) {
    hardsphere::state_exchange(*stepper_).scatter_state(slots_.owned_rows(), slots_.shifts(), x[0], v[0]);
    if (physics_.rough())
      hardsphere::state_exchange(*stepper_).scatter(hardsphere::SphereField::Omega, slots_.owned_rows(),
                                                    atom->omega[0]);
    if (virial_rows_) {  // only owned rows: a ghost's share is its owner's
      std::fill(virial_rows_, virial_rows_ + 6 * atom->nlocal, 0.0);
      hardsphere::state_exchange(*stepper_).take_sphere_virial(slots_.owned_rows(), virial_scale_, virial_rows_);
    }
    timer_.charge(PartTimer::Write);
    const OwnershipTally::Totals &c = tally_.totals();
    static_cast<hardsphere::WeightedCollisionTotals &>(t) = c - last_;
    last_ = c;
    const std::int64_t unresolved = stepper_->counters().unresolved_steps;
    t.unresolved = double(unresolved - last_unresolved_);
    last_unresolved_ = unresolved;
  }

  reneighbor_ = t.rerun ? shell_used_up() : shell_maybe_used_up();
  if (!reneighbor_ && other_lists_) reneighbor_ = lists_expired();
  timer_.charge(PartTimer::Moves);
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

StepTotals GhostPath::step_globally(bool check, const std::string &source, const std::string &hint) {
  // Re-run this step for all atoms at once with one standalone stepper (the same algorithm,
  // so the result a complete ghost shell gives), on every rank from the gathered start state;
  // each rank keeps its own atoms. Rare.
  const int nlocal = atom->nlocal;
  const bool rough = physics_.rough();
  const std::vector<double> mine = owned_atom_records(atom, rough);  // x and v still the step's start
  const int nprocs = comm->nprocs;
  int count = int(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(nprocs)), displs(static_cast<std::size_t>(nprocs), 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int r = 1; r < nprocs; r++) displs[std::size_t(r)] = displs[std::size_t(r - 1)] + counts[std::size_t(r - 1)];
  std::vector<double> all(std::size_t(displs.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);

  hardsphere::ParticleSystem sys = records_to_system(all, lammps_box(domain), rough);
  if (check) {  // validates and wraps, with the serial path's overlap tolerance
    try {
      hardsphere::validate_and_wrap(sys, source, nullptr, hardsphere::rounding_epsilon(hardsphere::Precision::Double));
    } catch (const std::exception &e) {
      error->all(FLERR, std::string(e.what()) + "; " + hint);
    }
  } else {
    hardsphere::wrap_periodic(sys);
  }
  hardsphere::ParticleSystem out;
  hardsphere::StepCounters c;
  try {
    auto global = hardsphere::make_stepper(sys, physics_, config_);
    auto &exch = hardsphere::state_exchange(*global);
    exch.set_sphere_virial(virial_rows_ != nullptr);
    global->run(1);
    out = global->state();
    c = global->counters();
    if (virial_rows_) take_owned_virial(exch);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: re-running a step for all atoms failed: ") + e.what());
  }

  // Owned atoms move by the stepper's displacement from where they started (LAMMPS keeps its
  // own periodic wrapping and image flags).
  double **x = atom->x, **v = atom->v;
  for (int i = 0; i < nlocal; i++) {
    const auto it = std::lower_bound(out.id.begin(), out.id.end(), std::int64_t(atom->tag[i]));
    const std::size_t k = std::size_t(it - out.id.begin());
    const Vec3d start{x[i][0], x[i][1], x[i][2]};
    Vec3d d = out.pos[k] - start;
    for (int a = 0; a < 3; a++)
      if (sys.box.periodic[a]) d[a] -= sys.box.length(a) * std::nearbyint(d[a] / sys.box.length(a));
    const Vec3d p = start + d;
    x[i][0] = p.x, x[i][1] = p.y, x[i][2] = p.z;
    v[i][0] = out.vel[k].x, v[i][1] = out.vel[k].y, v[i][2] = out.vel[k].z;
    if (rough)
      atom->omega[i][0] = out.omega[k].x, atom->omega[i][1] = out.omega[k].y, atom->omega[i][2] = out.omega[k].z;
  }
  StepTotals t;
  t.rerun = true;
  if (comm->me == 0) {  // the stepper counted every atom: rank 0 reports the totals
    static_cast<hardsphere::WeightedCollisionTotals &>(t) = hardsphere::collision_totals<double>(c);
    t.unresolved = double(c.unresolved_steps);
  }
  return t;
}

void GhostPath::take_owned_virial(hardsphere::StateExchange &exch) {
  // The engine holds every atom: this rank's shares go to its rows, found by tag.
  std::vector<std::int64_t> ids(exch.size());
  exch.copy_ids(ids.data());
  std::int64_t max_id = 0;
  for (const std::int64_t id : ids) max_id = std::max(max_id, id);
  std::vector<std::uint32_t> row_of_id(std::size_t(max_id) + 1, hardsphere::StateExchange::kNoRow);
  for (int i = 0; i < atom->nlocal; i++) row_of_id[std::size_t(atom->tag[i])] = std::uint32_t(i);
  std::vector<std::uint32_t> dest(ids.size());
  for (std::size_t k = 0; k < ids.size(); k++) dest[k] = row_of_id[std::size_t(ids[k])];
  std::fill(virial_rows_, virial_rows_ + 6 * atom->nlocal, 0.0);
  exch.take_sphere_virial(dest.data(), virial_scale_, virial_rows_);
}

void GhostPath::run_ends() {
  end_atoms_[0] = atom->nlocal, end_atoms_[1] = 0;
  for (int i = 0; i < atom->nlocal; i++) end_atoms_[1] += atom->tag[i];
  for (int d = 0; d < 3; d++)
    end_subdomain_[std::size_t(d)] = domain->sublo[d], end_subdomain_[std::size_t(d + 3)] = domain->subhi[d];
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
