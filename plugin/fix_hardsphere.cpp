#include "fix_hardsphere.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "ghost_path.h"
#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/stepper.hpp"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "output.h"
#include "pair_hardsphere.h"
#include "serial_path.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using hardsphere::format_number;

namespace {
constexpr int kVectorSize = 10;
}  // namespace

FixHardSphere::FixHardSphere(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  for (int a = 3; a < narg; a += 2) {
    const std::string key = arg[a];
    if (a + 1 >= narg) error->all(FLERR, "fix hardsphere: keyword '" + key + "' needs a value");
    const std::string val = arg[a + 1];
    if (key.rfind("wall_", 0) == 0) {
      a += wall_keyword(a, narg, arg) - 2;
    } else if (key == "detect") {
      if (val == "overlap")
        sweep = false;
      else if (val == "sweep")
        sweep = true;
      else
        error->all(FLERR, "fix hardsphere: detect must be 'overlap' or 'sweep', got '" + val + "'");
    } else if (key == "max_events") {
      max_events = utils::bnumeric(FLERR, arg[a + 1], false, lmp);
      if (max_events < 1) error->all(FLERR, "fix hardsphere: max_events must be >= 1");
    } else if (key == "restitution") {
      physics.restitution = utils::numeric(FLERR, arg[a + 1], false, lmp);
    } else if (key == "contact_time") {
      physics.contact_time = utils::numeric(FLERR, arg[a + 1], false, lmp);
      given.contact_time = true;
    } else if (key == "tangential_restitution") {
      physics.tangential_restitution = utils::numeric(FLERR, arg[a + 1], false, lmp);
    } else if (key == "friction") {
      physics.friction = utils::numeric(FLERR, arg[a + 1], false, lmp);
      given.friction = true;
    } else if (key == "inertia") {
      physics.inertia = utils::numeric(FLERR, arg[a + 1], false, lmp);
      given.inertia = true;
    } else if (key == "ghost") {
      if (val == "auto")
        ghost_auto = true;
      else if (val == "user")
        ghost_auto = false;
      else
        error->all(FLERR, "fix hardsphere: ghost must be 'auto' or 'user', got '" + val + "'");
    } else if (key == "timing") {
      if (val != "yes" && val != "no")
        error->all(FLERR, "fix hardsphere: timing must be 'yes' or 'no', got '" + val + "'");
      timing.enable(val == "yes");
    } else if (key == "path") {
      if (val == "auto")
        ghost_path_only = false;
      else if (val == "ghosts")
        ghost_path_only = true;
      else
        error->all(FLERR, "fix hardsphere: path must be 'auto' or 'ghosts', got '" + val + "'");
    } else {
      error->all(FLERR,
                 "fix hardsphere: unknown keyword '" + key +
                     "' (known: detect, max_events, restitution, contact_time, tangential_restitution, "
                     "friction, inertia, wall_restitution, wall_tangential_restitution, wall_friction, ghost, path, "
                     "timing)");
    }
  }
  try {  // gravity comes from fix gravity at setup, checked there against the boundaries
    physics = hardsphere::validated(physics, {false, false, false}, physics_names(), given);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: ") + e.what());
  }
  // Rough spheres carry LAMMPS's per-atom angular velocities (the atom style is set before
  // any fix can be defined).
  if (physics.rough() && !atom->omega_flag)
    error->all(FLERR, std::string("fix hardsphere: tangential_restitution needs per-atom angular velocities, which "
                                  "atom_style ") +
                          atom->atom_style + " does not have: use 'atom_style sphere'");
  time_integrate = 1;
  vector_flag = 1;
  size_vector = kVectorSize;
  global_freq = 1;
  extvector = 0;
  comm_forward = StepPath::forward_size(physics.rough());  // ghost velocities (owned + ghost path)
  virial_global_flag = 1;
  thermo_virial = 1;
  force_reneighbor = 1;
  next_reneighbor = -1;
  virial_peratom_flag = 1;  // compute stress/atom: the collision part (centroid stress the same)
  maxexchange = 6;          // vstep travels with migrating atoms
  create_attribute = 1;     // atoms created between runs start with no collision virial
  atom->add_callback(Atom::GROW);
}

int FixHardSphere::wall_keyword(int a, int narg, char **arg) {
  using hardsphere::WallSetting;
  const std::string key = arg[a];
  WallSetting setting = WallSetting::Restitution;
  if (key == "wall_tangential_restitution")
    setting = WallSetting::TangentialRestitution;
  else if (key == "wall_friction")
    setting = WallSetting::Friction;
  else if (key != "wall_restitution")
    error->all(FLERR, "fix hardsphere: unknown keyword '" + key +
                          "' (the wall keywords: wall_restitution, wall_tangential_restitution, wall_friction)");
  // 'KEY face value' when a face follows, else 'KEY value' for every wall.
  const std::string next = arg[a + 1];
  const bool face = next.find_first_of("0123456789.") == std::string::npos && next != "inf" && next != "INF";
  if (face && a + 2 >= narg) error->all(FLERR, "fix hardsphere: " + key + " " + next + " needs a value");
  const std::string face_name = face ? next : "";
  if (!wall_keys_seen.insert(key + " " + face_name).second)
    error->all(FLERR, "fix hardsphere: " + key + (face ? " " + face_name : "") + " is given twice; give it once");
  const double value = utils::numeric(FLERR, arg[a + (face ? 2 : 1)], false, lmp);
  try {
    hardsphere::set_wall_law(physics, given, setting, face_name, value, key);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: ") + e.what());
  }
  return face ? 3 : 2;
}

FixHardSphere::~FixHardSphere() {
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(vstep);
}

int FixHardSphere::setmask() { return INITIAL_INTEGRATE | POST_FORCE | PRE_NEIGHBOR; }

void FixHardSphere::init() {
  initialised = true;
  serial = comm->nprocs == 1 && !ghost_path_only;
  check_input();  // fix_hardsphere_checks.cpp: styles, box, run style, other fixes, neighbour settings
  dt = update->dt;
  others.scan(modify, this);
  // Per-atom virials only where a compute asks for them (the same on every rank).
  atom_virial = false;
  for (int i = 0; i < modify->ncompute; i++) atom_virial |= modify->compute[i]->pressatomflag != 0;
  if (atom_virial && !vstep) {
    grow_arrays(atom->nmax);
    vstep_at = -1;
  } else if (!atom_virial) {
    memory->destroy(vstep);
    vstep_rows = 0;
  }
  if (!path) {
    if (serial)
      path = std::make_unique<SerialPath>(lmp, timing, others);
    else
      path = std::make_unique<GhostPath>(lmp, this, timing);
  }
  if (serial) static_cast<SerialPath &>(*path).set_kinematic_bits(kinematic_bits);
  const double shell = serial ? 0.0 : GhostPath::ghost_cutoff(force->pair->cutforce, neighbor->skin);
  check_ghost_cutoff(ghost_auto ? shell : 0.0);
  if (serial) return;  // the stepper needs no ghost shell and no LAMMPS neighbour list

  // One shell for every atom: mode multi sizes LAMMPS's shells per type from the neighbour
  // cutoffs, thinner than this path needs ('ghost auto' raises the single-mode cutoff only).
  if (comm->mode != Comm::SINGLE)
    error->all(FLERR,
               "fix hardsphere: 'comm_modify mode multi' gives each atom type its own, thinner ghost shell; "
               "use 'comm_modify mode single' on more than one rank or with 'path ghosts'");

  // Raise the user ghost cutoff (comm_modify cutoff) to the shell the owned + ghost path needs
  // unless 'ghost user' was given. No LAMMPS neighbour list: each rank's stepper makes its own.
  if (ghost_auto) {
    if (comm->cutghostuser < shell) {
      comm->cutghostuser = shell;
      if (comm->me == 0)
        utils::logmesg(
            lmp, "fix hardsphere: ghost cutoff raised to " + format_number(shell) +
                     " (3 x contact distance + 2 x skin) so the ghosts an owned atom meets see all their partners\n");
    }
  }
}

void FixHardSphere::reset_dt() { dt = update->dt; }

void FixHardSphere::setup_pre_neighbor() { path->neighbours_changed(); }

void FixHardSphere::pre_neighbor() { path->neighbours_changed(); }

void FixHardSphere::setup(int vflag) {
  // rerun reads snapshots and takes no step: no stepper, and no overlap check on positions that
  // the dump rounded. The snapshot's pressure has no collision part.
  in_rerun = hardsphere_rerun_in_progress(lmp);
  after_rerun = in_rerun;
  if (in_rerun) {
    v_init(vflag);
    if (vflag_global)
      for (double &w : virial) w = 0.0;
    return;
  }
  check_setup();
  skip_reverse_comm();
  read_walls();
  read_gravity();
  positions_kept = false;  // the run's start reads every atom anew
  path->configure(stepper_config(), physics);
  path->run_starts();
  t_now = temperature_now();
  run_set_up = true;
  // Thermo at a run's first step reports the last resolved step's collision virial (zero
  // before any step): setup resolves no collisions itself.
  report_step_virial(vflag);
}

void FixHardSphere::check_setup() {
  const int nlocal = atom->nlocal;
  double *radius = atom->radius, *rmass = atom->rmass, **v = atom->v;
  double v2max = 0.0;
  for (int i = 0; i < nlocal; i++) {
    v2max = std::max(v2max, v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    if (!(radius[i] > 0.0) || !(rmass[i] > 0.0))
      error->one(FLERR, "fix hardsphere: atom " + std::to_string(atom->tag[i]) + " has radius " +
                            format_number(radius[i]) + " and mass " + format_number(rmass[i]) +
                            "; both must be positive (set them in the data file)");
  }
  MPI_Allreduce(MPI_IN_PLACE, &v2max, 1, MPI_DOUBLE, MPI_MAX, world);

  check_contact_distances();
  check_timestep();
  // Time step against the skin: within one step an atom moves at most ~2 v_max dt.
  const double vmax = std::sqrt(v2max);
  if (4.0 * vmax * dt >= neighbor->skin)
    error->all(FLERR, "fix hardsphere: timestep too large for the neighbour skin: 4 * v_max * dt = " +
                          format_number(4.0 * vmax * dt) + " >= skin " + format_number(neighbor->skin) +
                          "; reduce 'timestep' or raise the skin ('neighbor <skin> bin')");

  if (!serial) check_big_spheres_mpi();
  // Overlapping pairs at the start are refused where the atoms are handed to a stepper.
}

void FixHardSphere::check_contact_distances() {
  // The pair style's contact distance per type pair must cover the per-atom diameters, of the
  // atoms there are and of those a fix will insert (fix pour, fix deposit: extract("radius")).
  auto *pair = dynamic_cast<PairHardSphere *>(force->pair_match("hardsphere", 1));
  const int nt = atom->ntypes;
  double *radius = atom->radius;
  std::vector<double> rmax(nt + 1, 0.0), grmax(nt + 1, 0.0);
  for (int i = 0; i < atom->nlocal; i++) rmax[atom->type[i]] = std::max(rmax[atom->type[i]], radius[i]);
  for (int t = 1; t <= nt; t++) rmax[t] = std::max(rmax[t], OtherFixes::inserted_radius(modify, t));
  MPI_Allreduce(rmax.data(), grmax.data(), nt + 1, MPI_DOUBLE, MPI_MAX, world);
  for (int a = 1; a <= nt; a++)
    for (int b = a; b <= nt; b++)
      if (grmax[a] > 0 && grmax[b] > 0 && grmax[a] + grmax[b] > pair->contact(a, b) * (1 + 1e-12))
        error->all(FLERR, "fix hardsphere: atoms of types " + std::to_string(a) + " and " + std::to_string(b) +
                              " reach contact at " + format_number(grmax[a] + grmax[b]) + " but pair_coeff gives " +
                              format_number(pair->contact(a, b)) +
                              "; raise that pair_coeff diameter or use 'pair_coeff * *'");
}

void FixHardSphere::initial_integrate(int vflag) {
  if (!initialised)
    error->all(FLERR,
               "fix hardsphere was defined after the last run's setup, which 'run ... pre no' skips: "
               "start the first run after 'fix hardsphere' with its setup ('run N' without 'pre no')");
  if (!run_set_up) {  // 'run ... pre no' skips setup(); 'timestep' in between only sets update->dt
    if (after_rerun)
      error->all(FLERR,
                 "fix hardsphere: 'run ... pre no' right after 'rerun' would start from the last snapshot "
                 "without checking it; start the run with its setup ('run N' without 'pre no')");
    check_fixes_unchanged();
    skip_reverse_comm();
    dt = update->dt;
    check_timestep();
    path->configure(stepper_config(), physics);
  }
  if (!gravity_fixes.empty()) take_gravity();
  if (!region_fixes.empty()) take_wall_turns();
  // Another fix may have moved atoms at the end of the last step (x was kept at post_force).
  const bool moved = positions_kept && positions_moved();
  positions_kept = false;
  const StepStart start{!run_set_up, others.acted(update->ntimestep - 1), moved ? moved_source() : std::string()};
  run_set_up = true;
  if (path->before_step(start)) t_now = temperature_now();
  const bool take_atom_virial = wants_atom_virial(vflag);
  add_step(path->step(take_atom_virial ? vstep[0] : nullptr, force->mvv2e / dt));
  if (take_atom_virial) vstep_at = update->ntimestep;
  if (temperature_varies()) t_now = temperature_of(path->owned_mv2());
  t_integral += t_now * dt;
  if (path->needs_reneighbor()) {  // LAMMPS decides after this hook: re-neighbour in this step
    next_reneighbor = update->ntimestep;
    n_forced += 1;
  }
}

void FixHardSphere::add_step(const StepTotals &t) {
  n_coll_step = t.collisions;
  for (int k = 0; k < 6; k++) step_virial[k] = t.pair_virial_tensor[std::size_t(k)];
  n_coll += n_coll_step;
  virial_sum += t.pair_virial;
  n_wall += t.wall_collisions;
  n_unresolved += t.unresolved;
  if (t.rerun) n_global += 1;
  sim_time += dt;
}

void FixHardSphere::post_run() {
  if (in_rerun) {
    in_rerun = false;
    return;
  }
  timing.report(lmp, world, long(update->nsteps));
  timing.reset();
  if (path) path->run_ends();
  run_set_up = false;                                   // a following 'run ... pre no' starts without setup()
  if (newton_saved >= 0) force->newton = newton_saved;  // the user's setting between runs
  newton_saved = -1;
}

void FixHardSphere::post_force(int vflag) {
  // The step was taken in initial_integrate; report its collision virial.
  report_step_virial(vflag);
  // LAMMPS has re-neighboured (if it does in this step) and holds this step's positions; keep
  // them if a fix acting at the end of the step may move atoms (the next step compares).
  positions_kept = others.may_move(update->ntimestep);
  if (positions_kept && atom->nlocal > 0)
    x_kept.assign(atom->x[0], atom->x[0] + 3 * atom->nlocal);
  else
    x_kept.clear();
}

void FixHardSphere::report_step_virial(int vflag) {
  // The stepper's sums are mass x velocity x distance; LAMMPS's virial is in energy units.
  v_init(vflag);
  if (vflag_global)
    for (int k = 0; k < 6; k++) virial[k] = step_virial[k] / dt * force->mvv2e;
  // Per atom, the same step's share (already in energy units); zero (v_init) if none was taken.
  if (vflag_atom && vstep && vstep_at == update->ntimestep)
    for (int i = 0; i < atom->nlocal; i++)
      for (int k = 0; k < 6; k++) vatom[i][k] = vstep[i][k];
}

std::string FixHardSphere::moved_source() const {
  return "fix hardsphere: after " + others.movers() + " at step " + std::to_string(update->ntimestep - 1);
}

bool FixHardSphere::wants_atom_virial(int vflag) const {
  return atom_virial && thermo_virial && (vflag & (VIRIAL_ATOM | VIRIAL_CENTROID)) != 0;
}

void FixHardSphere::grow_arrays(int nmax) {
  if (!atom_virial) return;
  vstep_rows = std::max(nmax, 1);  // one row at least: a rank without atoms still has the array
  memory->grow(vstep, vstep_rows, 6, "hardsphere:vstep");
}

void FixHardSphere::set_arrays(int i) {
  if (atom_virial)
    for (int k = 0; k < 6; k++) vstep[i][k] = 0.0;
}

void FixHardSphere::copy_arrays(int i, int j, int) {
  if (atom_virial)
    for (int k = 0; k < 6; k++) vstep[j][k] = vstep[i][k];
}

int FixHardSphere::pack_exchange(int i, double *buf) {
  if (!atom_virial) return 0;
  for (int k = 0; k < 6; k++) buf[k] = vstep[i][k];
  return 6;
}

int FixHardSphere::unpack_exchange(int nlocal, double *buf) {
  if (!atom_virial) return 0;
  for (int k = 0; k < 6; k++) vstep[nlocal][k] = buf[k];
  return 6;
}

double FixHardSphere::memory_usage() { return double(vstep_rows) * 6 * sizeof(double); }

double FixHardSphere::temperature_of(double local_mv2) const {
  double all = 0.0;
  MPI_Allreduce(&local_mv2, &all, 1, MPI_DOUBLE, MPI_SUM, world);
  return atom->natoms > 0 ? all / (3.0 * double(atom->natoms)) : 0.0;
}

double FixHardSphere::temperature_now() const {
  double mv2 = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *v = atom->v[i];
    mv2 += atom->rmass[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  return temperature_of(mv2);
}

bool FixHardSphere::positions_moved() const {
  // x_kept holds the owned rows as they were before the other fixes' step-end hooks (see
  // post_force); LAMMPS neither re-orders nor wraps atoms between those hooks and this step.
  const int nlocal = atom->nlocal;
  int moved = x_kept.size() != std::size_t(3 * nlocal) ||
              (nlocal > 0 && !std::equal(atom->x[0], atom->x[0] + 3 * nlocal, x_kept.begin()));
  MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_INT, MPI_MAX, world);
  return moved != 0;
}

hardsphere::StepperConfig FixHardSphere::stepper_config() const {
  hardsphere::StepperConfig cfg;
  cfg.dt = dt;
  cfg.detect = sweep ? hardsphere::Detect::Sweep : hardsphere::Detect::Overlap;
  cfg.max_events_per_step = max_events;
  cfg.names = physics_names();  // the keywords in the library's advice
  return cfg;
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
  // <T> is m v^2 / 3: energy after mvv2e, and N <T> / V pressure after nktv2p (1 in lj units).
  return natoms * t_mean * z / (domain->xprd * domain->yprd * domain->zprd) * force->mvv2e * force->nktv2p;
}

int FixHardSphere::pack_forward_comm(int n, int *list_, double *buf, int pbc_flag, int *pbc) {
  return path->pack_forward(n, list_, buf, pbc_flag, pbc);
}

void FixHardSphere::unpack_forward_comm(int n, int first, double *buf) { path->unpack_forward(n, first, buf); }
