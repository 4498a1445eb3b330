#include "fix_hardsphere.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "hardsphere/errors.hpp"
#include "hardsphere/stepper.hpp"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair_hardsphere.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using hardsphere::kNoImage;

namespace {
constexpr int kVectorSize = 10;
std::string num(double x) {
  char b[64];
  snprintf(b, sizeof(b), "%.6g", x);
  return b;
}
}  // namespace

FixHardSphere::FixHardSphere(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  for (int a = 3; a < narg; a += 2) {
    const std::string key = arg[a];
    if (a + 1 >= narg) error->all(FLERR, "fix hardsphere: keyword '" + key + "' needs a value");
    const std::string val = arg[a + 1];
    if (key == "detect") {
      if (val == "overlap")
        sweep = false;
      else if (val == "sweep")
        sweep = true;
      else
        error->all(FLERR, "fix hardsphere: detect must be 'overlap' or 'sweep', got '" + val + "'");
    } else if (key == "max_events") {
      max_events = utils::bnumeric(FLERR, arg[a + 1], false, lmp);
      if (max_events < 1) error->all(FLERR, "fix hardsphere: max_events must be >= 1");
    } else if (key == "ghost") {
      if (val == "auto")
        ghost_auto = true;
      else if (val == "user")
        ghost_auto = false;
      else
        error->all(FLERR, "fix hardsphere: ghost must be 'auto' or 'user', got '" + val + "'");
    } else if (key == "path") {
      if (val == "auto")
        ghost_path_only = false;
      else if (val == "ghosts")
        ghost_path_only = true;
      else
        error->all(FLERR, "fix hardsphere: path must be 'auto' or 'ghosts', got '" + val + "'");
    } else {
      error->all(FLERR, "fix hardsphere: unknown keyword '" + key + "' (known: detect, max_events, ghost, path)");
    }
  }
  time_integrate = 1;
  vector_flag = 1;
  size_vector = kVectorSize;
  global_freq = 1;
  extvector = 0;
  comm_forward = 4;  // velocity and drift mirrors (wall_axes) of ghosts
  virial_global_flag = 1;
  thermo_virial = 1;
  maxexchange = 7;  // wall_axes and start travel with their atom
  force_reneighbor = 1;
  next_reneighbor = -1;
  for (auto &s : zero_shift) s = V3{0, 0, 0};

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  for (int i = 0; i < atom->nlocal; i++) wall_axes[i] = 0.0;
}

FixHardSphere::~FixHardSphere() {
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(wall_axes);
  memory->destroy(start);
}

int FixHardSphere::setmask() { return INITIAL_INTEGRATE | POST_FORCE | PRE_NEIGHBOR; }

void FixHardSphere::init() {
  check_input();  // fix_hardsphere_checks.cpp: styles, box, run style, other fixes, neighbour settings
  dt = update->dt;
  serial = comm->nprocs == 1 && !ghost_path_only;
  serial_schedule();  // also tells the owned + ghost path when to re-measure the temperature
  if (serial) {
    list = nullptr;
    return;  // the stepper needs no ghost shell and no LAMMPS neighbour list
  }

  // Chains of collisions reach across the ghost boundary: with ghosts out to twice the
  // neighbour cutoff, every ghost within one cutoff of this sub-domain has a complete list.
  // Raise the user ghost cutoff (comm_modify cutoff) to that unless 'ghost user' was given.
  if (ghost_auto) {
    const double need = ghost_factor * (force->pair->cutforce + neighbor->skin);
    if (comm->cutghostuser < need) {
      comm->cutghostuser = need;
      if (comm->me == 0)
        utils::logmesg(lmp, "fix hardsphere: ghost cutoff raised to " + num(need) +
                                " (2 x neighbour cutoff) so collision chains near sub-domain faces are seen\n");
    }
  }

  int irequest = neighbor->request(this, instance_me);
  neighbor->requests[irequest]->pair = 0;
  neighbor->requests[irequest]->fix = 1;
  // Half list (each pair once) over owned and ghost atoms, ghost-ghost pairs included; the
  // fix makes the both-direction adjacency from it.
  neighbor->requests[irequest]->half = 1;
  neighbor->requests[irequest]->full = 0;
  neighbor->requests[irequest]->newton = 2;
  neighbor->requests[irequest]->ghost = 1;
}

void FixHardSphere::init_list(int, NeighList *ptr) { list = ptr; }

void FixHardSphere::reset_dt() { dt = update->dt; }

void FixHardSphere::record_build() {
  const int nall = atom->nlocal + atom->nghost;
  xbuild.resize(nall);
  for (int i = 0; i < nall; i++) xbuild[i] = V3{atom->x[i][0], atom->x[i][1], atom->x[i][2]};
  max_disp2 = 0.0;
  adjacency_dirty = true;
}

void FixHardSphere::setup_pre_neighbor() {
  if (serial)
    slots_dirty = true;
  else
    record_build();
}

void FixHardSphere::pre_neighbor() {
  if (serial)
    lammps_moved = true;  // LAMMPS has wrapped and may have sorted its atoms
  else
    record_build();
}

void FixHardSphere::setup(int vflag) {
  check_setup();
  if (serial) serial_setup();
  t_now = temperature_now();
  run_set_up = true;
  for (int i = 0; i < atom->nlocal; i++) wall_axes[i] = 0.0;
  // Thermo at a run's first step reports the last resolved step's collision virial (zero
  // before any step): setup resolves no collisions itself.
  v_init(vflag);
  if (vflag_global)
    for (int k = 0; k < 6; k++) virial[k] = step_virial[k] / dt;
}

void FixHardSphere::check_setup() {
  const int nlocal = atom->nlocal;
  double *radius = atom->radius, *rmass = atom->rmass, **v = atom->v;
  // Uniform radius and mass select the equal-mass kernel, as in the standalone stepper.
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (int i = 0; i < nlocal; i++) {
    lo[0] = std::min(lo[0], radius[i]), hi[0] = std::max(hi[0], radius[i]);
    lo[1] = std::min(lo[1], rmass[i]), hi[1] = std::max(hi[1], rmass[i]);
    const double v2 = v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2];
    hi[2] = std::max(hi[2], v2);
    if (!(radius[i] > 0.0) || !(rmass[i] > 0.0))
      error->one(FLERR, "fix hardsphere: atom " + std::to_string(atom->tag[i]) + " has radius " + num(radius[i]) +
                            " and mass " + num(rmass[i]) + "; both must be positive (set them in the data file)");
  }
  double glo[2], ghi[3];
  MPI_Allreduce(lo, glo, 2, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(hi, ghi, 3, MPI_DOUBLE, MPI_MAX, world);
  mono = glo[0] == ghi[0] && glo[1] == ghi[1];
  mono_sigma = 2.0 * glo[0];
  mono_mass = glo[1];

  // The pair style's contact distance per type pair must cover the per-atom diameters.
  auto *pair = dynamic_cast<PairHardSphere *>(force->pair_match("hardsphere", 1));
  const int nt = atom->ntypes;
  std::vector<double> rmax(nt + 1, 0.0), grmax(nt + 1, 0.0);
  for (int i = 0; i < nlocal; i++) rmax[atom->type[i]] = std::max(rmax[atom->type[i]], radius[i]);
  MPI_Allreduce(rmax.data(), grmax.data(), nt + 1, MPI_DOUBLE, MPI_MAX, world);
  for (int a = 1; a <= nt; a++)
    for (int b = a; b <= nt; b++)
      if (grmax[a] > 0 && grmax[b] > 0 && grmax[a] + grmax[b] > pair->contact(a, b) * (1 + 1e-12))
        error->all(FLERR, "fix hardsphere: atoms of types " + std::to_string(a) + " and " + std::to_string(b) +
                              " reach contact at " + num(grmax[a] + grmax[b]) + " but pair_coeff gives " +
                              num(pair->contact(a, b)) + "; raise that pair_coeff diameter or use 'pair_coeff * *'");

  // Time step against the skin: within one step an atom moves at most ~2 v_max dt.
  const double vmax = std::sqrt(ghi[2]);
  if (4.0 * vmax * dt >= neighbor->skin)
    error->all(FLERR,
               "fix hardsphere: timestep too large for the neighbour skin: 4 * v_max * dt = " + num(4.0 * vmax * dt) +
                   " >= skin " + num(neighbor->skin) + "; reduce 'timestep' or raise the skin ('neighbor <skin> bin')");

  // No overlapping pairs at the start (a collision cannot be rewound from inside a sphere);
  // the serial path checks that when it hands the atoms to the stepper.
  if (serial) return;
  if (!list) error->all(FLERR, "fix hardsphere: neighbour list missing");
  long long overlaps = 0;
  std::string example;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jl = list->firstneigh[i];
    for (int k = 0; k < list->numneigh[i]; k++) {
      const int j = jl[k] & NEIGHMASK;
      const double dx = atom->x[i][0] - atom->x[j][0], dy = atom->x[i][1] - atom->x[j][1],
                   dz = atom->x[i][2] - atom->x[j][2];
      const double s = radius[i] + radius[j];
      const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (d < s * (1.0 - 1e-9)) {
        if (overlaps++ == 0)
          example = "atoms " + std::to_string(atom->tag[i]) + " and " + std::to_string(atom->tag[j]) +
                    " are at distance " + num(d) + " < contact distance " + num(s);
      }
    }
  }
  long long all = 0;
  MPI_Allreduce(&overlaps, &all, 1, MPI_LONG_LONG, MPI_SUM, world);
  if (all > 0) {
    const std::string msg = "fix hardsphere: " + std::to_string(all) + " overlapping pair(s) at setup";
    if (overlaps > 0) error->one(FLERR, msg + ", e.g. " + example + "; start from a non-overlapping state");
    error->all(FLERR, msg + "; start from a non-overlapping state");
  }
}

void FixHardSphere::initial_integrate(int) {
  if (serial) {
    serial_step();
    return;
  }
  if (!run_set_up || others_acted(update->ntimestep - 1)) t_now = temperature_now();
  run_set_up = true;
  t_integral += t_now * dt;
  double **x = atom->x, **v = atom->v;
  const int nlocal = atom->nlocal;
  n_wall_start = n_wall;
  for (int i = 0; i < nlocal; i++) {
    // The step may have to be re-run from its start (resolve_globally): keep the velocity and
    // the displacement, which unlike the position survive LAMMPS's re-wrapping and sorting.
    start[i][0] = dt * v[i][0], start[i][1] = dt * v[i][1], start[i][2] = dt * v[i][2];
    start[i][3] = v[i][0], start[i][4] = v[i][1], start[i][5] = v[i][2];
    x[i][0] += dt * v[i][0];
    x[i][1] += dt * v[i][1];
    x[i][2] += dt * v[i][2];
    wall_axes[i] = 0.0;
  }
  if (domain->xperiodic && domain->yperiodic && domain->zperiodic) return;
  // LAMMPS loses atoms outside fixed faces: mirror them back in for its communication and
  // neighbour lists. post_force() undoes the mirrors and lets the resolver bounce them in time
  // order with the collisions (as the standalone stepper does).
  for (int i = 0; i < nlocal; i++) {
    int axes = 0;
    for (int d = 0; d < 3; d++) {
      if (domain->periodicity[d]) continue;
      const double before = x[i][d];
      if (hardsphere::kernel::reflect_from_walls(x[i][d], v[i][d], domain->boxlo[d], domain->boxhi[d],
                                                 atom->radius[i]) != 0.0) {
        axes |= 1 << d;
        start[i][d] += x[i][d] - before;  // the mirror is part of this step's move
      }
    }
    wall_axes[i] = double(axes);
  }
}

void FixHardSphere::build_adjacency() {
  // Both directions, CSR over owned + ghost atoms, from the half ghost list (ghost
  // coordinates are image-shifted already: every pair has image code kNoImage).
  const int nall = atom->nlocal + atom->nghost;
  if (std::uint32_t(nall) > hardsphere::kMaxAdjIndex + 1)
    error->one(FLERR, "fix hardsphere: " + std::to_string(nall) + " owned + ghost atoms on one rank, at most " +
                          std::to_string(hardsphere::kMaxAdjIndex + 1));
  adj_start.assign(nall + 1, 0);
  const int nlisted = list->inum + list->gnum;
  for (int ii = 0; ii < nlisted; ii++) {
    const int i = list->ilist[ii];
    const int *jl = list->firstneigh[i];
    adj_start[i + 1] += list->numneigh[i];
    for (int k = 0; k < list->numneigh[i]; k++) adj_start[(jl[k] & NEIGHMASK) + 1]++;
  }
  for (int i = 0; i < nall; i++) adj_start[i + 1] += adj_start[i];
  adj.resize(adj_start[nall]);
  std::vector<std::uint32_t> cursor(adj_start.begin(), adj_start.end() - 1);
  for (int ii = 0; ii < nlisted; ii++) {
    const int i = list->ilist[ii];
    const int *jl = list->firstneigh[i];
    for (int k = 0; k < list->numneigh[i]; k++) {
      const int j = jl[k] & NEIGHMASK;
      adj[cursor[i]++] = hardsphere::adj_entry(std::uint32_t(j), kNoImage);
      adj[cursor[j]++] = hardsphere::adj_entry(std::uint32_t(i), kNoImage);
    }
  }

  adjacency_dirty = false;
}

void FixHardSphere::note_disp(int k, const V3 &p) {
  const V3 d = p - xbuild[k];
  max_disp2 = std::max(max_disp2, hardsphere::dot(d, d));
}

void FixHardSphere::unmirror(int k) {
  // Inverse of the drift's mirror on each flagged axis: the straight path continues past the
  // face it crossed (the one the mirrored velocity now points away from).
  const int axes = int(wall_axes[k]);
  for (int d = 0; d < 3; d++) {
    if (!(axes & (1 << d))) continue;
    const double contact = vel[k][d] < 0.0 ? domain->boxhi[d] - rad[k] : domain->boxlo[d] + rad[k];
    pos[k][d] = 2.0 * contact - pos[k][d];
    vel[k][d] = -vel[k][d];
  }
}

void FixHardSphere::on_collision(int i, int j, double back) {
  // The resolver has moved i and j to their end-of-step positions with the new velocities:
  // rewind both by `back` to get the separation at contact; the impulse is m dv.
  const V3 ci = pos[i] - back * vel[i], cj = pos[j] - back * vel[j];
  const V3 r = ci - cj;
  const V3 dp = mass[i] * (vel[i] - vprev[i]);
  const int nlocal = atom->nlocal;
  const int lower = tags[i] < tags[j] ? i : j;
  if (lower < nlocal) {  // counted once over all ranks and periodic images
    n_coll_step += 1;
    step_virial[0] += r.x * dp.x;
    step_virial[1] += r.y * dp.y;
    step_virial[2] += r.z * dp.z;
    step_virial[3] += r.x * dp.y;
    step_virial[4] += r.x * dp.z;
    step_virial[5] += r.y * dp.z;
  }
  if ((i < nlocal) != (j < nlocal)) met_owned[i < nlocal ? j : i] = 1;
  vprev[i] = vel[i];
  vprev[j] = vel[j];
  note_disp(i, ci), note_disp(j, cj), note_disp(i, pos[i]), note_disp(j, pos[j]);
}

bool FixHardSphere::ghosts_agree_with_owners() {
  // A ghost copy evolves from what this rank sees around it. A collision chain that runs out
  // past the ghost shell (ghosts near its outer edge miss partners) can give a ghost another
  // history than its owner, and an owned atom that met that ghost a wrong result. Every such
  // case shows as a ghost that met an owned atom and ended the step with another velocity
  // than its owner (if the owned atom should have met the ghost but did not, its own ghost on
  // the owner's side met that owner and disagrees there). Owners' final velocities are sent
  // to the ghosts and compared; rounding differs between copies by ~1e-15.
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  v_owner.resize(nall);
  comm_mode = 1;
  comm->forward_comm_fix(this, 3);
  comm_mode = 0;
  int bad = 0;
  for (int g = nlocal; g < nall; g++) {
    if (!met_owned[g]) continue;
    const V3 d = vel[g] - v_owner[g];
    const double scale = 1.0 + std::sqrt(hardsphere::dot(v_owner[g], v_owner[g]));
    if (!(std::sqrt(hardsphere::dot(d, d)) <= 1e-9 * scale)) bad = 1;
  }
  int any = 0;
  MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, world);
  return any == 0;
}

void FixHardSphere::resolve_globally() {
  // Re-run this step for all atoms at once with the standalone stepper (the same algorithm,
  // so the same result a consistent ghost shell gives), on every rank from the same gathered
  // start state; each rank keeps its own atoms. Rare: counted in f_ID[6].
  const int nlocal = atom->nlocal;
  constexpr int kFields = 10;  // tag, type, radius, mass, x[3], v[3]
  std::vector<double> mine(std::size_t(nlocal) * kFields);
  for (int i = 0; i < nlocal; i++) {
    double *o = &mine[std::size_t(i) * kFields];
    o[0] = double(atom->tag[i]), o[1] = atom->type[i], o[2] = atom->radius[i], o[3] = atom->rmass[i];
    o[4] = x_start[i].x, o[5] = x_start[i].y, o[6] = x_start[i].z;
    o[7] = start[i][3], o[8] = start[i][4], o[9] = start[i][5];
  }
  const int nprocs = comm->nprocs;
  int count = nlocal * kFields;
  std::vector<int> counts(nprocs), displs(nprocs, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int r = 1; r < nprocs; r++) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<double> all(std::size_t(displs[nprocs - 1] + counts[nprocs - 1]));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);

  hardsphere::ParticleSystem sys = empty_system();
  for (std::size_t k = 0; k < all.size(); k += kFields) {
    const double *o = &all[k];
    sys.push_back(std::int64_t(o[0]), int(o[1]), o[2], o[3], {o[4], o[5], o[6]}, {o[7], o[8], o[9]});
  }
  hardsphere::wrap_periodic(sys);
  hardsphere::ParticleSystem out;
  hardsphere::StepCounters c;
  try {
    auto global = new_stepper(sys);
    global->run(1);
    out = global->state();
    c = global->counters();
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: re-running a step for all atoms failed: ") + e.what());
  }

  // Owned atoms move by the stepper's displacement from where they started (LAMMPS keeps its
  // own periodic wrapping and image flags).
  double **x = atom->x, **v = atom->v;
  for (int i = 0; i < nlocal; i++) {
    const std::int64_t tag = std::int64_t(atom->tag[i]);
    const auto it = std::lower_bound(out.id.begin(), out.id.end(), tag);
    const std::size_t k = std::size_t(it - out.id.begin());
    hardsphere::Vec3d d = out.pos[k] - x_start[i];
    for (int a = 0; a < 3; a++)
      if (sys.box.periodic[a]) d[a] -= sys.box.length(a) * std::nearbyint(d[a] / sys.box.length(a));
    const V3 p = x_start[i] + d;
    x[i][0] = p.x, x[i][1] = p.y, x[i][2] = p.z;
    v[i][0] = out.vel[k].x, v[i][1] = out.vel[k].y, v[i][2] = out.vel[k].z;
    note_disp(i, p);
  }
  // Totals of the step: the stepper counted every atom, so rank 0 reports them.
  n_wall = n_wall_start;
  n_coll_step = 0;
  std::fill(step_virial, step_virial + 6, 0.0);
  if (comm->me == 0) {
    n_wall += double(c.wall_collisions);
    n_coll_step = double(c.collisions);
    for (int k = 0; k < 6; k++) step_virial[k] = c.pair_virial_tensor[k];
    n_unresolved += double(c.unresolved_steps);
  }
  n_global += 1;
}

template <bool Mono>
struct FixHardSphere::Hooks {
  FixHardSphere &f;
  int first = -1;
  // The resolver reports the two spheres of a collision one after the other.
  void after_collision(std::uint32_t k, double back) {
    if (first < 0) {
      first = int(k);
      return;
    }
    const int i = first;
    first = -1;
    f.on_collision(i, int(k), back);
  }
  void after_bounce(std::uint32_t k) {
    if (int(k) < f.atom->nlocal) f.n_wall += 1;  // a ghost's bounce is counted by its owner
    f.vprev[k] = f.vel[k];
    f.note_disp(int(k), f.pos[k]);
  }
  HS_ALWAYS_INLINE void prefetch(std::uint32_t k) const {
    __builtin_prefetch(&f.xbuild[k]);
    __builtin_prefetch(&f.vprev[k]);
    __builtin_prefetch(&f.tags[k]);
  }
  bool must_rescan() const { return false; }  // lists cannot be rebuilt inside a LAMMPS step
  bool rescan(double) { return true; }
};

void FixHardSphere::post_run() {
  if (serial && stepper && !state_written) serial_write();  // a run cut short (timer timeout)
  run_set_up = false;                                       // a following 'run ... pre no' starts without setup()
}

void FixHardSphere::post_force(int vflag) {
  if (serial) {  // the step was taken in initial_integrate; report its collision virial
    v_init(vflag);
    if (vflag_global)
      for (int k = 0; k < 6; k++) virial[k] = step_virial[k] / dt;
    return;
  }
  // Ghosts need the owners' current velocities and drift mirrors.
  comm->forward_comm_fix(this);
  if (adjacency_dirty) build_adjacency();

  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  double **x = atom->x, **v = atom->v;
  pos.resize(nall), vel.resize(nall), rad.resize(nall), mass.resize(nall), tags.resize(nall);
  for (int i = 0; i < nall; i++) {
    pos[i] = V3{x[i][0], x[i][1], x[i][2]};
    vel[i] = V3{v[i][0], v[i][1], v[i][2]};
    rad[i] = atom->radius[i];
    mass[i] = atom->rmass[i];
    tags[i] = std::int64_t(atom->tag[i]);
  }
  met_owned.assign(nall, 0);
  x_start.resize(nlocal);  // where the owned atoms started this step, in LAMMPS's current wrapping
  for (int i = 0; i < nlocal; i++) x_start[i] = pos[i] - V3{start[i][0], start[i][1], start[i][2]};
  for (int i = 0; i < nall; i++)
    if (wall_axes[i] != 0.0) unmirror(i);
  vprev = vel;
  // Straight paths past a face bound the path to it: checking their ends covers the bounce.
  for (int i = 0; i < nlocal; i++) note_disp(i, pos[i]);
  n_coll_step = 0;
  std::fill(step_virial, step_virial + 6, 0.0);

  if (mono) {
    res_mono.set_uniform(mono_sigma, mono_mass);
    resolve_step(res_mono);
  } else {
    resolve_step(res_poly);
  }
  for (int i = 0; i < nlocal; i++) {
    x[i][0] = pos[i].x, x[i][1] = pos[i].y, x[i][2] = pos[i].z;
    v[i][0] = vel[i].x, v[i][1] = vel[i].y, v[i][2] = vel[i].z;
  }
  if (!ghosts_agree_with_owners()) resolve_globally();
  n_coll += n_coll_step;
  for (int k = 0; k < 3; k++) virial_sum += step_virial[k];
  sim_time += dt;

  // Safety of the neighbour list. Every position visited in this step (ends of drift,
  // contacts, ends of step) was checked against the list's build positions: more than half
  // the skin means a pair could have been missed. Otherwise force a rebuild before the next
  // step if it could get there (an atom moves <= ~2 v_max dt per step, collisions included).
  double loc[2] = {max_disp2, 0.0}, glob[2];
  for (int i = 0; i < nlocal; i++) loc[1] = std::max(loc[1], hardsphere::dot(vel[i], vel[i]));
  MPI_Allreduce(loc, glob, 2, MPI_DOUBLE, MPI_MAX, world);
  const double dmax = std::sqrt(glob[0]), vmax = std::sqrt(glob[1]), skin = neighbor->skin;
  if (2.0 * dmax > skin)
    error->all(FLERR, "fix hardsphere: an atom moved " + num(dmax) +
                          " since the last neighbour list build, more than "
                          "half the skin " +
                          num(skin) +
                          ", so a collision may have been missed; reduce 'timestep' or "
                          "raise the skin ('neighbor <skin> bin')");
  if (2.0 * (dmax + 2.0 * vmax * dt) > skin && next_reneighbor != update->ntimestep + 1) {
    next_reneighbor = update->ntimestep + 1;
    n_forced += 1;
  }

  v_init(vflag);
  if (vflag_global)
    for (int k = 0; k < 6; k++) virial[k] = step_virial[k] / dt;
}

template <bool Mono>
void FixHardSphere::resolve_step(hardsphere::ContactResolver<double, Mono> &res) {
  const int nall = atom->nlocal + atom->nghost;
  res.reset(std::size_t(nall), dt);
  res.set_event_limit(max_events);
  // Ghosts carry their own coordinates: no entry has an image, so every row is plain.
  res.bind({pos.data(), vel.data(), rad.data(), mass.data(), tags.data(), nullptr, adj_start.data(), adj.data(),
            zero_shift, nullptr, adj_start.data() + 1});
  double v2max = 0;
  for (int i = 0; i < nall; i++) v2max = std::max(v2max, hardsphere::dot(vel[i], vel[i]));
  res.set_speed_bound(std::sqrt(v2max));
  res.set_walls({domain->periodicity[0] != 0, domain->periodicity[1] != 0, domain->periodicity[2] != 0},
                {domain->boxlo[0], domain->boxlo[1], domain->boxlo[2]},
                {domain->boxhi[0], domain->boxhi[1], domain->boxhi[2]});

  // Scan: each pair once (j > i) of the both-direction adjacency.
  res.clear_candidates();
  const double reach = sweep ? 2.0 * std::sqrt(v2max) * dt : 0.0;
  for (int i = 0; i < nall; i++) {
    const V3 pi = pos[i];
    for (std::uint32_t k = adj_start[i]; k < adj_start[i + 1]; k++) {
      const std::uint32_t j = hardsphere::adj_partner(adj[k]);
      if (j <= std::uint32_t(i)) continue;
      const V3 dr = pi - pos[j];
      const double sg = Mono ? mono_sigma : rad[i] + rad[j];
      const double lim = sg + reach;
      if (hardsphere::dot(dr, dr) < lim * lim) res.consider(std::uint32_t(i), j, kNoImage, dr, sg, !sweep);
    }
  }
  res.predict_all_walls();
  if (res.has_candidates()) {
    Hooks<Mono> hooks{*this};
    hardsphere::ContactTally tally;
    res.resolve(hooks, tally);
    n_unresolved += double(tally.unresolved_steps);
  }
  res.end_step();
}

double FixHardSphere::temperature_now() const {
  double mv2 = 0.0, all = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *v = atom->v[i];
    mv2 += atom->rmass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  MPI_Allreduce(&mv2, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return atom->natoms > 0 ? all / (3.0 * double(atom->natoms)) : 0.0;
}

double FixHardSphere::compute_vector(int n) {
  double loc[8] = {n_coll, n_coll_step, virial_sum, sim_time, n_wall, n_global, n_forced, n_unresolved};
  if (n == 3 || n == 5 || n == 6) return loc[n];  // identical on every rank
  const int k = n < 8 ? n : 2;                    // Z and P need the summed collision virial
  double all = 0;
  MPI_Allreduce(&loc[k], &all, 1, MPI_DOUBLE, MPI_SUM, world);
  if (n < 8) return all;
  // Z = PV/(NkT) = 1 + W / (3 N <T> t) as the standalone computes it (W: collision virial,
  // <T>: time-averaged 2 KE / (3N), t: simulated time); P = N <T> Z / V with V the box volume.
  const double natoms = double(atom->natoms), t_mean = sim_time > 0.0 ? t_integral / sim_time : t_now;
  const double z = sim_time > 0.0 && natoms > 0.0 && t_integral > 0.0 ? 1.0 + all / (3.0 * natoms * t_integral) : 1.0;
  if (n == 8) return z;
  return natoms * t_mean * z / (domain->xprd * domain->yprd * domain->zprd);
}

int FixHardSphere::pack_forward_comm(int n, int *list_, double *buf, int, int *) {
  double **v = atom->v;
  int m = 0;
  for (int k = 0; k < n; k++) {
    const int j = list_[k];
    if (comm_mode == 1 && j >= atom->nlocal) {  // a ghost passed on: its owner's value
      buf[m++] = v_owner[j].x;
      buf[m++] = v_owner[j].y;
      buf[m++] = v_owner[j].z;
      continue;
    }
    buf[m++] = v[j][0];
    buf[m++] = v[j][1];
    buf[m++] = v[j][2];
    if (comm_mode == 0) buf[m++] = wall_axes[j];
  }
  return m;
}

void FixHardSphere::unpack_forward_comm(int n, int first, double *buf) {
  double **v = atom->v;
  int m = 0;
  for (int i = first; i < first + n; i++) {
    if (comm_mode == 1) {  // owners' final velocities, kept apart from the ghosts' own results
      v_owner[i] = V3{buf[m], buf[m + 1], buf[m + 2]};
      m += 3;
      continue;
    }
    v[i][0] = buf[m++];
    v[i][1] = buf[m++];
    v[i][2] = buf[m++];
    wall_axes[i] = buf[m++];
  }
}

void FixHardSphere::grow_arrays(int nmax) {
  memory->grow(wall_axes, nmax, "hardsphere:wall_axes");
  memory->grow(start, nmax, 6, "hardsphere:start");
}

void FixHardSphere::copy_arrays(int i, int j, int) {
  wall_axes[j] = wall_axes[i];
  for (int k = 0; k < 6; k++) start[j][k] = start[i][k];
}

int FixHardSphere::pack_exchange(int i, double *buf) {
  buf[0] = wall_axes[i];
  for (int k = 0; k < 6; k++) buf[1 + k] = start[i][k];
  return 7;
}

int FixHardSphere::unpack_exchange(int nlocal, double *buf) {
  wall_axes[nlocal] = buf[0];
  for (int k = 0; k < 6; k++) start[nlocal][k] = buf[1 + k];
  return 7;
}

double FixHardSphere::memory_usage() {
  const double n = double(pos.size());
  return double(atom->nmax) * 7 * sizeof(double) + n * (4 * sizeof(V3) + 2 * sizeof(double) + 9) +
         double(adj.size()) * 4;
}
