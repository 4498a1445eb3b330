// What fix hardsphere refuses at init, and the neighbour settings it sets for itself. Every
// refusal names the command or value at fault and what to use instead (docs/fix_hardsphere.md,
// "Restrictions"). Hard spheres have no forces and no potential energy: a fix that adds or acts
// on forces would change nothing, so it is refused rather than silently ignored.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_gravity.h"
#include "fix_hardsphere.h"
#include "fix_move.h"
#include "fix_setforce.h"
#include "fix_wall_hardsphere.h"
#include "fix_wall_hardsphere_region.h"
#include "force.h"
#include "group.h"
#include "hardsphere/format.hpp"
#include "hardsphere/particles.hpp"
#include "modify.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;
using namespace FixConst;
using hardsphere::format_number;

namespace {

// neigh_modify every: large enough that LAMMPS never re-neighbours on its own schedule.
constexpr int kFixDecides = 1 << 30;

// FixSetForce keeps its per-axis settings protected. A class derived from it may form pointers
// to those members, and such a member pointer applies to any FixSetForce object.
struct SetForceAxes : FixSetForce {
  //! True for 'fix ID group setforce NULL NULL NULL': an axis given as NULL has no variable name
  //! and style 0 (NONE in LAMMPS's fix_setforce.cpp; a number sets 1, a variable its name).
  static bool all_null(Fix *fix) {
    auto *f = static_cast<FixSetForce *>(fix);
    int FixSetForce::*const styles[3] = {&SetForceAxes::xstyle, &SetForceAxes::ystyle, &SetForceAxes::zstyle};
    char *FixSetForce::*const names[3] = {&SetForceAxes::xstr, &SetForceAxes::ystr, &SetForceAxes::zstr};
    for (int d = 0; d < 3; d++)
      if (f->*names[d] != nullptr || f->*styles[d] != 0) return false;
    return true;
  }
};

//! FixGravity keeps whether its magnitude and direction are constant protected: read it the same way.
struct GravityStyle : FixGravity {
  //! True for a fix gravity whose vector is set once (numbers, no variables): varflag is then
  //! CONSTANT (0 in LAMMPS's fix_gravity.cpp) and the vector is set in its constructor.
  static bool constant(Fix *fix) { return static_cast<FixGravity *>(fix)->*(&GravityStyle::varflag) == 0; }
};

//! FixMove keeps its style private. An explicit instantiation may name a private member, and
//! hands its pointer out here (the one standard way to read it without changing LAMMPS).
int FixMove::*move_style_member();
template <int FixMove::*M>
struct MoveStyleMember {
  friend int FixMove::*move_style_member() { return M; }
};
template struct MoveStyleMember<&FixMove::mstyle>;

//! fix move's style by name: LINEAR, WIGGLE, ROTATE, VARIABLE (and TRANSROT since 2023), in
//! LAMMPS's fix_move.cpp order.
std::string move_style(Fix *fix) {
  static const char *const names[] = {"linear", "wiggle", "rotate", "variable", "transrot"};
  const int s = static_cast<FixMove *>(fix)->*move_style_member();
  return s >= 0 && s < 5 ? names[s] : "style " + std::to_string(s);
}

bool is_style(const Fix *f, const char *name) { return std::string(f->style) == name; }

//! Monte Carlo insertions and deletions weigh them by the pair energy, which hard spheres do not
//! have (pour, deposit and evaporate are followed: OtherFixes).
bool exchanges_atoms_by_energy(const Fix *f) {
  for (const char *s : {"gcmc", "charge/regulation"})
    if (is_style(f, s)) return true;
  return false;
}

//! The stages inside a step (between the start of the step and end_of_step) named in `mask`.
std::string in_step_stages(int mask) {
  const struct {
    int bit;
    const char *name;
  } stages[] = {{INITIAL_INTEGRATE | INITIAL_INTEGRATE_RESPA, "initial_integrate"},
                {POST_INTEGRATE | POST_INTEGRATE_RESPA, "post_integrate"},
                {FINAL_INTEGRATE | FINAL_INTEGRATE_RESPA, "final_integrate"}};
  std::string out;
  for (const auto &s : stages)
    if (mask & s.bit) out += (out.empty() ? "" : ", ") + std::string(s.name);
  return out;
}

// The stages a fix's mask may name: acting on forces, moving atoms inside the step.
constexpr int kForceStages = PRE_FORCE | PRE_FORCE_RESPA | PRE_REVERSE | POST_FORCE | POST_FORCE_RESPA;
constexpr int kMoveStages = INITIAL_INTEGRATE | INITIAL_INTEGRATE_RESPA | POST_INTEGRATE | POST_INTEGRATE_RESPA |
                            FINAL_INTEGRATE | FINAL_INTEGRATE_RESPA;

std::string fix_name(const Fix *f) { return "fix " + std::string(f->id) + " (" + f->style + ")"; }

}  // namespace

void FixHardSphere::check_timestep() const {
  if (dt > 0.0 && std::isfinite(dt)) return;
  char given[64];
  snprintf(given, sizeof(given), "%.6g", dt);
  error->all(FLERR, std::string("fix hardsphere: 'timestep ") + given + "': the time step must be positive and finite");
}

void FixHardSphere::check_input() {
  if (!atom->style_match("sphere") || !atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, "fix hardsphere needs per-atom radius and mass: use 'atom_style sphere'");
  if (igroup != 0)
    error->all(FLERR, std::string("fix hardsphere must act on group 'all', not '") + group->names[igroup] +
                          "' (every atom is a hard sphere)");
  if (update->whichflag == 2)
    error->all(FLERR, "fix hardsphere: hard spheres have no potential energy to minimise; use 'run'");
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, std::string("fix hardsphere: run_style ") + update->integrate_style +
                          " is not supported (hard spheres have no forces to split into levels); use 'run_style "
                          "verlet'");
  // Bonded interactions would act as forces, which the fix never applies, and LAMMPS's
  // special_bonds would keep bonded pairs out of the pair style, which the steppers do not.
  const struct {
    bigint count;
    const char *what, *command, *style;
  } topology[] = {{atom->nbonds, "bonds", "bond_style", force->bond_style},
                  {atom->nangles, "angles", "angle_style", force->angle_style},
                  {atom->ndihedrals, "dihedrals", "dihedral_style", force->dihedral_style},
                  {atom->nimpropers, "impropers", "improper_style", force->improper_style}};
  for (const auto &t : topology)
    if (t.count > 0)
      error->all(FLERR, "fix hardsphere: the system has " + std::to_string(t.count) + " " + t.what + " (" + t.command +
                            " " + (t.style ? t.style : "none") +
                            "), but hard spheres interact only by collisions: bonded forces would not act and "
                            "bonded pairs would still collide; use atoms without bonds (e.g. atom_style sphere)");
  // A hybrid style that holds hardsphere next to others would add forces the fix never applies.
  if (force->pair_match("hardsphere", 1) && force->pair_style && std::string(force->pair_style) != "hardsphere")
    error->all(FLERR, std::string("fix hardsphere: pair_style ") + force->pair_style +
                          " combines hardsphere with other pair styles, whose forces fix hardsphere would never "
                          "apply (hard spheres move by collisions only); use 'pair_style hardsphere' alone");
  if (!force->pair_match("hardsphere", 1))
    error->all(FLERR,
               "fix hardsphere needs 'pair_style hardsphere' and 'pair_coeff * *' (contact distances and the "
               "neighbour cutoff); pair hybrid is not supported");
  if (domain->dimension != 3) error->all(FLERR, "fix hardsphere: 'dimension 2' is not supported; use 'dimension 3'");
  if (domain->triclinic)
    error->all(FLERR, "fix hardsphere supports orthogonal boxes only: create the box without tilt factors");
  // Shrink-wrapped faces follow the atoms, which LAMMPS also reports as a changing box: name
  // the boundary before blaming box-changing fixes.
  const char axis[3] = {'x', 'y', 'z'}, letter[4] = {'p', 'f', 's', 'm'};
  for (int d = 0; d < 3; d++)
    for (int s = 0; s < 2; s++)
      if (domain->boundary[d][s] >= 2)
        error->all(FLERR, std::string("fix hardsphere: boundary '") + letter[domain->boundary[d][s]] + "' on " +
                              axis[d] +
                              ": shrink-wrapped faces move; use 'f' (fixed walls, spheres bounce off them) or 'p'");
  // The cell grid, walls and periodic images are set up for one box. Fixes that only move the
  // sub-domain boundaries between ranks (fix balance) leave it alone.
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i]->box_change & (Fix::BOX_CHANGE_SIZE | Fix::BOX_CHANGE_SHAPE))
      error->all(FLERR, std::string("fix hardsphere needs a fixed box: fix ") + modify->fix[i]->id + " (" +
                            modify->fix[i]->style +
                            ") changes it; remove it (compress hard spheres by growing their radii between runs, "
                            "'set ... diameter', instead)");
  if (domain->box_change_size || domain->box_change_shape)
    error->all(FLERR,
               "fix hardsphere needs a fixed box: remove what changes it (compress hard spheres by growing their "
               "radii between runs, 'set ... diameter', instead)");
  // The steppers find pairs in their own cells, not in LAMMPS's lists: an exclusion would not
  // let the excluded spheres pass through each other.
  if (neighbor->nex_type || neighbor->nex_group || neighbor->nex_mol)
    error->all(FLERR,
               "fix hardsphere: 'neigh_modify exclude' is not supported (every pair of hard spheres collides); "
               "use 'neigh_modify exclude none'");
  check_other_fixes();
  // A box may start empty when a fix inserts atoms during the run (fix pour, fix deposit).
  bool inserting = false;
  for (int i = 0; i < modify->nfix; i++)
    inserting |= OtherFixes::is_atom_changer(modify->fix[i]) && !is_style(modify->fix[i], "evaporate");
  if (atom->natoms == 0 && !inserting)
    error->all(FLERR,
               "fix hardsphere: the box has no atoms; create or read them (create_atoms, read_data) before 'run', "
               "or insert them during it (fix pour, fix deposit)");
  apply_neighbor_settings();
}

void FixHardSphere::check_other_fixes() {
  gravity_fixes.clear();
  wall_fixes.clear();
  region_fixes.clear();
  fixes_at_init.clear();
  for (int i = 0; i < modify->nfix; i++) fixes_at_init.emplace_back(modify->fix[i]->id);
  kinematic_bits = 0;
  // fix move integrates its group itself; the stepper follows only straight, constant motion, which
  // a fix freeze group with its velocity set gives (its atoms keep their velocity under fix hardsphere).
  for (int i = 0; i < modify->nfix; i++) {
    Fix *f = modify->fix[i];
    if (!is_style(f, "move")) continue;
    const std::string style = move_style(f);
    if (style == "linear")
      error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                            " linear moves its group itself; for a piston of infinite mass on a straight line use "
                            "'fix ID " +
                            group->names[f->igroup] + " freeze' and 'velocity " + group->names[f->igroup] +
                            " set VX VY VZ' instead (under fix hardsphere a fix freeze group keeps its velocity)");
    error->all(FLERR, "fix hardsphere: " + fix_name(f) + " " + style +
                          " is not followed: hard-sphere obstacles move on straight lines at constant velocity "
                          "(a fix freeze group with its velocity set, 'velocity GROUP set VX VY VZ'); remove it");
  }
  // Refused by what each fix tells LAMMPS it does (its mask): acting on forces (pre_force,
  // pre_reverse, post_force, with their rRESPA variants), moving atoms inside the step
  // (initial/post/final_integrate), or changing the atoms between steps (pre_exchange). Fixes
  // acting only at end_of_step (thermostats by velocity scaling, averages, output), at
  // re-neighbouring or only in minimisations are allowed, as are 'setforce NULL NULL NULL'
  // (sets nothing), store/force (records the zero forces), balance (load balancing), dynamic
  // groups and heat/flow with add/heat (per-atom temperatures).
  // Most specific first: another integrator, then fixes that insert or delete atoms by energy.
  for (int i = 0; i < modify->nfix; i++) {
    Fix *f = modify->fix[i];
    if (f != this && f->time_integrate)
      error->all(
          FLERR,
          std::string("fix hardsphere is the time integrator") +
              (physics.rough() ? " of positions, velocities and angular velocities (tangential_restitution)" : "") +
              ": remove " + fix_name(f));
  }
  for (int i = 0; i < modify->nfix; i++)
    if (exchanges_atoms_by_energy(modify->fix[i]))
      error->all(FLERR, "fix hardsphere: " + fix_name(modify->fix[i]) +
                            " exchanges atoms by Monte Carlo moves weighed by a pair energy, which hard spheres do "
                            "not have: remove it (fix pour, fix deposit and fix evaporate are followed)");
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i] != this) check_other_fix(modify->fix[i], modify->fmask[i]);
}

void FixHardSphere::check_other_fix(Fix *f, int mask) {
  if (is_style(f, "store/force") || is_style(f, "balance")) return;
  // Its atoms are kinematic spheres: infinite mass, moving on at the velocity they have (LAMMPS's
  // fix freeze zeroes forces only, so an atom moving at the start moves on), no gravity.
  if (is_style(f, "freeze")) {
    if (!serial)
      error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                            " (kinematic spheres) runs on one rank only for now: run on one rank without 'path "
                            "ghosts', or remove it");
    kinematic_bits |= f->groupbit;
    return;
  }
  // fix pour, deposit and evaporate change the atoms in their pre_exchange on the steps they
  // schedule; both paths write LAMMPS's rows before and take the new atoms up after (OtherFixes).
  if (OtherFixes::is_atom_changer(f)) return;
  // A dynamic group's fix (post_integrate in LAMMPS 2021) only reads positions to set its
  // members; both paths write them on its steps (OtherFixes::reads).
  if (is_style(f, "GROUP")) return;
  // Per-atom temperatures integrated from heat flows (fix property/atom temperature heatflow):
  // in the force stages and final_integrate, but on neither forces, positions nor velocities.
  // Hard-sphere collisions conduct no heat; sources such as add/heat act as they would.
  if (is_style(f, "heat/flow") || is_style(f, "add/heat")) return;
  if (is_style(f, "setforce") && SetForceAxes::all_null(f)) return;
  if (is_style(f, "gravity")) {  // acts through the stepper's parabolic flights (read_gravity)
    if (f->igroup != 0)
      error->all(FLERR, "fix hardsphere: " + fix_name(f) + " acts on group '" + group->names[f->igroup] +
                            "', but every atom is a hard sphere: use group all");
    gravity_fixes.push_back(f);
    return;
  }
  if (is_style(f, "wall/hardsphere")) {  // its walls join the physics at setup (read_walls)
    wall_fixes.push_back(static_cast<FixWallHardSphere *>(f));
    return;
  }
  if (is_style(f, "wall/hardsphere/region")) {
    region_fixes.push_back(static_cast<FixWallHardSphereRegion *>(f));
    return;
  }
  if (is_style(f, "wall/gran/region"))
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " is a wall fix, which hard spheres would not feel (they have no forces): use 'fix " + f->id +
                          " all wall/hardsphere/region REGION-ID' with the same region and the hard-sphere law "
                          "(restitution E, tangential_restitution B, friction MU)");
  if (utils::strmatch(f->style, "^wall/"))
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " is a wall fix, which hard spheres would not feel (they have no forces): use 'fix " + f->id +
                          " all wall/hardsphere' with the same wall (xplane|yplane|zplane LO HI, zcylinder "
                          "RADIUS) and the hard-sphere law (restitution E, friction MU, ...), or 'boundary f' "
                          "on that axis (the box faces are walls)");
  if (is_style(f, "adapt"))
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " changes parameters during a run, which fix hardsphere takes only at a run's start: "
                          "remove it and change diameters between runs ('set ... diameter')");
  // Its end-of-step position correction is for a Verlet integrator's O(dt^3) error; flights are
  // exact, and the stepper would not take up positions changed between its steps.
  if (is_style(f, "ehex"))
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " corrects positions at the end of each step (for a Verlet integrator's error; "
                          "hard-sphere flights are exact): use fix heat, the same heat exchange without that "
                          "correction");
  if (is_style(f, "dt/reset"))
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " changes the timestep during a run; hard spheres need a fixed 'timestep' "
                          "(4 v_max dt < skin): remove it");
  // A Python callback at post_force may do anything, inside the step: not a force fix.
  if (is_style(f, "python/invoke") && (mask & kForceStages))
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " calls its Python function at post_force, inside the time step, where fix hardsphere "
                          "owns positions and velocities: call it at the end of the step ('fix " +
                          f->id +
                          " all python/invoke N end_of_step FUNCTION'), where fix hardsphere takes up what "
                          "it changes");
  if (mask & kForceStages) {
    std::string hint;
    if (utils::strmatch(f->style, "^langevin") || utils::strmatch(f->style, "^viscous"))
      hint = " (thermostat with an end-of-step fix instead, e.g. temp/berendsen or temp/rescale)";
    else if (is_style(f, "setforce"))
      hint = " ('setforce NULL NULL NULL', which sets nothing, is allowed)";
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " adds or acts on forces, but hard spheres have no forces (fix hardsphere moves them "
                          "by collisions only), so it would have no effect: remove it" +
                          hint);
  }
  if (mask & kMoveStages)
    error->all(FLERR, "fix hardsphere: " + fix_name(f) + " moves atoms inside the time step (" + in_step_stages(mask) +
                          "), where fix hardsphere owns positions and velocities: remove it (fixes acting at "
                          "the end of a step, e.g. temp/berendsen, temp/rescale or momentum, are allowed)");
  if (mask & PRE_EXCHANGE)
    error->all(FLERR, "fix hardsphere: " + fix_name(f) +
                          " changes atoms between steps (pre_exchange: inserting, deleting, moving or retyping "
                          "them), which fix hardsphere does not follow within a run: remove it");
}

void FixHardSphere::apply_neighbor_settings() {
  // LAMMPS reads these settings in Neighbor::init(), after the fixes' init(), so they hold from
  // this run on. Serial: LAMMPS's own check every step keeps its wrapping and sorting regular
  // (the stepper needs no LAMMPS list). Owned + ghost path: re-neighbouring refreshes the ghosts
  // each rank's stepper is made from, and the fix asks for it exactly when an atom could have
  // used up the ghost shell's slack (ghost_checks.cpp); LAMMPS's own checks would only make
  // the steppers again more often.
  const int every = serial ? 1 : kFixDecides;
  const Neighbor *nb = neighbor;
  if (nb->every == every && nb->delay == 0 && nb->dist_check == 1 && nb->build_once == 0) return;
  const std::string was = "every " + std::to_string(nb->every) + " delay " + std::to_string(nb->delay) + " check " +
                          (nb->dist_check ? "yes" : "no") + (nb->build_once ? " once yes" : "");
  neighbor->every = every;
  neighbor->delay = 0;
  neighbor->dist_check = 1;
  neighbor->build_once = 0;
  if (comm->me == 0 && !neigh_noted)
    utils::logmesg(lmp, serial ? "fix hardsphere: neighbour lists set to 'neigh_modify every 1 delay 0 check yes' "
                                 "(were '" +
                                     was + "'): hard spheres need the lists checked every step\n"
                               : "fix hardsphere: neighbour lists rebuilt only when the fix asks (were '" + was +
                                     "'): on the owned + ghost path it re-neighbours when an atom could reach past "
                                     "the ghost shell\n");
  neigh_noted = true;
}

void FixHardSphere::skip_reverse_comm() {
  // With newton on, LAMMPS clears and sends back the forces and torques of every ghost each
  // step; hard spheres (the only pair style allowed, no bonds) put none there. The integrator
  // reads force->newton every step: set at a run's start (not in init(), which write_data and
  // velocity call too), restored by post_run().
  if (!force->newton || atom->molecular != Atom::ATOMIC) return;
  newton_saved = force->newton;
  force->newton = 0;
  if (comm->me == 0 && !newton_noted)
    utils::logmesg(lmp,
                   "fix hardsphere: ghost forces are not communicated back during runs (as with 'newton off'): "
                   "hard spheres exert no forces\n");
  newton_noted = true;
}

void FixHardSphere::check_fixes_unchanged() {
  // A run without setup ('pre no'): the other fixes were checked (and LAMMPS listed them) at
  // the last init, so none may have come or gone, and fix gravity (found again: a replaced one
  // leaves a stale pointer) is read again before the first step (take_gravity).
  bool same = int(fixes_at_init.size()) == modify->nfix;
  for (int i = 0; same && i < modify->nfix; i++) same = fixes_at_init[std::size_t(i)] == modify->fix[i]->id;
  gravity_fixes.clear();
  wall_fixes.clear();
  region_fixes.clear();
  for (int i = 0; i < modify->nfix; i++) {
    if (is_style(modify->fix[i], "gravity")) gravity_fixes.push_back(modify->fix[i]);
    if (is_style(modify->fix[i], "wall/hardsphere"))
      wall_fixes.push_back(static_cast<FixWallHardSphere *>(modify->fix[i]));
    if (is_style(modify->fix[i], "wall/hardsphere/region"))
      region_fixes.push_back(static_cast<FixWallHardSphereRegion *>(modify->fix[i]));
  }
  if (!same || walls_text() != walls_at_setup)
    error->all(FLERR,
               "fix hardsphere: fixes were added, removed or replaced since the last run's setup, which 'run ... "
               "pre no' skips: start this run with its setup ('run N' without 'pre no')");
}

void FixHardSphere::read_walls() {
  // The walls of every fix wall/hardsphere, validated with the rest of the physics in read_gravity.
  physics.shapes.clear();
  for (const FixWallHardSphere *f : wall_fixes)
    physics.shapes.insert(physics.shapes.end(), f->shapes().begin(), f->shapes().end());
  region_first.clear();
  for (const FixWallHardSphereRegion *f : region_fixes) {
    region_first.push_back(physics.shapes.size());
    physics.shapes.insert(physics.shapes.end(), f->shapes().begin(), f->shapes().end());
  }
  walls_at_setup = walls_text();
}

void FixHardSphere::take_wall_turns() {
  // A region's 'rotate v_theta': its rate over this step, from its variable now and one step on.
  for (std::size_t i = 0; i < region_fixes.size(); i++)
    for (const auto &[k, omega] : region_fixes[i]->rates()) {
      hardsphere::WallShape &w = physics.shapes.at(region_first.at(i) + k);
      if (w.omega == omega) continue;
      w.omega = omega;
      try {
        path->set_shape_rotation(region_first[i] + k, omega);
      } catch (const std::exception &e) {
        error->all(FLERR,
                   std::string("fix hardsphere: at step ") + std::to_string(update->ntimestep) + ": " + e.what());
      }
    }
}

std::string FixHardSphere::walls_text() const {
  std::string text;
  for (const FixWallHardSphere *f : wall_fixes)
    for (const hardsphere::WallShape &w : f->shapes()) text += hardsphere::describe(w) + "\n";
  for (const FixWallHardSphereRegion *f : region_fixes)
    for (const hardsphere::WallShape &w : f->shapes()) text += hardsphere::describe(w) + "\n";
  return text;
}

std::array<double, 3> FixHardSphere::gravity_now(bool settled) const {
  // fix gravity's vector is a force per mass (m g is added to f); as an acceleration it takes
  // ftm2v, as in LAMMPS's integrators (1 in lj, si and cgs units).
  std::array<double, 3> gravity{0.0, 0.0, 0.0};
  const int self = modify->find_fix(id);
  for (Fix *f : gravity_fixes) {
    // A fix gravity with variables sets its vector in its setup (post_force), which runs after
    // this fix's when it was defined later: the first step takes it up (take_gravity).
    if (settled && !GravityStyle::constant(f) && modify->find_fix(f->id) > self) continue;
    int dim = 0;
    const auto *g = static_cast<const double *>(f->extract("gvec", dim));
    if (!g) error->all(FLERR, "fix hardsphere: cannot read the acceleration of fix " + std::string(f->id));
    for (int d = 0; d < 3; d++) gravity[std::size_t(d)] += g[d] * force->ftm2v;
  }
  return gravity;
}

void FixHardSphere::read_gravity() {
  // The acceleration of every fix gravity (LAMMPS has set it in the fixes' init or setup);
  // flights are parabolas, along any axis (a chute: periodic along the flow).
  physics.gravity = gravity_now(true);
  const std::array<bool, 3> periodic{domain->periodicity[0] != 0, domain->periodicity[1] != 0,
                                     domain->periodicity[2] != 0};
  try {
    physics = hardsphere::validated(physics, periodic, physics_names(), given);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: ") + e.what());
  }
  flow_warned = false;
  warn_unbounded_flow();
}

void FixHardSphere::warn_unbounded_flow() {
  // A chute that cannot settle runs, and says why: once a run (a turning gravity changes the text).
  if (flow_warned) return;
  const std::string flow = hardsphere::unbounded_flow(
      physics, {domain->periodicity[0] != 0, domain->periodicity[1] != 0, domain->periodicity[2] != 0},
      physics_names());
  if (flow.empty()) return;
  flow_warned = true;
  if (comm->me == 0) error->warning(FLERR, "fix hardsphere: " + flow);
}

void FixHardSphere::take_gravity() {
  std::array<double, 3> g{};
  try {
    g = hardsphere::validated_gravity(gravity_now(false), physics_names());
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: at step ") + std::to_string(update->ntimestep) + ": " + e.what());
  }
  if (g == physics.gravity) return;
  physics.gravity = g;
  path->set_gravity(g);
  warn_unbounded_flow();
}

void FixHardSphere::check_ghost_cutoff(double shell) const {
  // LAMMPS copies every atom into each periodic image within its ghost cutoff, the largest of the
  // neighbour cutoff (contact distance + skin), comm_modify cutoff and the shell this fix asks
  // for, looping and allocating by it without bound (a skin of 1e300 never returns). The pair
  // style has kept each contact distance within half a box length; beyond kMaxGhostBoxes box
  // lengths (2 x 3 + 1 = 7 copies per axis) the cutoff can only come from the skin or the user's
  // ghost cutoff, and serves nothing the fix needs.
  constexpr double kMaxGhostBoxes = 3.0;
  const double contact = force->pair->cutforce, skin = neighbor->skin;
  const double neighbour = contact + skin, cutoff = std::max({neighbour, comm->cutghostuser, shell});
  const char axis[3] = {'x', 'y', 'z'};
  for (int d = 0; d < 3; d++) {
    if (!domain->periodicity[d] || cutoff <= kMaxGhostBoxes * domain->prd[d]) continue;
    std::string source = "contact distance " + format_number(contact) + " + skin " + format_number(skin);
    std::string remedy = "use a smaller skin ('neighbor SKIN bin')";
    if (cutoff == comm->cutghostuser && cutoff > neighbour && cutoff > shell) {
      source = "comm_modify cutoff", remedy = "use a smaller comm_modify cutoff";
    } else if (cutoff == shell && cutoff > neighbour) {
      source = "3 x contact distance + 2 x skin " + format_number(skin) + ", the owned + ghost path's shell";
    }
    error->all(FLERR, "fix hardsphere: LAMMPS's ghost cutoff " + format_number(cutoff) + " (" + source + ") exceeds " +
                          format_number(kMaxGhostBoxes) + " periodic box lengths along " + axis[d] + " (" +
                          format_number(kMaxGhostBoxes * domain->prd[d]) +
                          "), where LAMMPS would copy every atom into more than 7 images per axis; " + remedy);
  }
}

void FixHardSphere::check_big_spheres_mpi() {
  // The stepper finds a few big spheres' partners in their own pass (kBigOverMedian), but the
  // MPI path's ghost shell is a few contact distances of the largest sphere, so one big sphere
  // would make most of the box ghosts on every rank. The same rule as the stepper's, from a
  // median found by bisection over global counts (no rank holds every radius).
  const int nlocal = atom->nlocal;
  const double *radius = atom->radius;
  double lo = INFINITY, hi = 0;
  for (int i = 0; i < nlocal; i++) lo = std::min(lo, radius[i]), hi = std::max(hi, radius[i]);
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_DOUBLE, MPI_MAX, world);
  if (!(hi > hardsphere::kBigOverMedian * lo)) return;
  const auto count_above = [&](double r) {
    std::int64_t c = 0;
    for (int i = 0; i < nlocal; i++) c += radius[i] > r;
    MPI_Allreduce(MPI_IN_PLACE, &c, 1, MPI_INT64_T, MPI_SUM, world);
    return c;
  };
  // Smallest radius with at most half the atoms above it: the median of split_by_size.
  const std::int64_t half = std::int64_t(atom->natoms / 2);
  double a = lo, b = hi;
  for (int k = 0; k < 80 && b > a * (1 + 1e-14); k++) {
    const double m = std::sqrt(a * b);
    (count_above(m) > half ? a : b) = m;
  }
  const std::int64_t big = count_above(hardsphere::kBigOverMedian * b);
  if (big == 0 || big > std::int64_t(hardsphere::kMaxBigSpheres)) return;
  error->all(FLERR, fmt::format("fix hardsphere: {} atom(s) have a diameter above {} x the median diameter {:.6g} "
                                "(largest {:.6g}): such big spheres run on one MPI rank only, where the stepper finds "
                                "their partners in a pass of their own (the MPI path's ghost shell would be sized by "
                                "the largest sphere); run this input on 1 rank",
                                big, hardsphere::kBigOverMedian, 2 * b, 2 * hi));
}
