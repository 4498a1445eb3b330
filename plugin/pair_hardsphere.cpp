#include "pair_hardsphere.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_hardsphere.h"
#include "force.h"
#include "hardsphere/format.hpp"
#include "input.h"
#include "lammps_compat.h"
#include "memory.h"
#include "modify.h"
#include "other_fixes.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;
using hardsphere::format_number;

PairHardSphere::PairHardSphere(LAMMPS *lmp) : Pair(lmp) {
  single_enable = 1;
  restartinfo = 1;
  no_virial_fdotr_compute = 1;  // the collision virial comes from fix hardsphere
  writedata = 1;
}

PairHardSphere::~PairHardSphere() {
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(cut);
    memory->destroy(diam);
  }
}

void PairHardSphere::allocate() {
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  memory->create(cut, n + 1, n + 1, "pair:cut");
  memory->create(diam, n + 1, n + 1, "pair:diam");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
}

void PairHardSphere::compute(int eflag, int vflag) {
  // Hard spheres have no force and no potential energy: the fix moves the atoms.
  ev_init(eflag, vflag);
}

void PairHardSphere::settings(int narg, char **) {
  if (narg != 0) error->all(FLERR, "pair_style hardsphere takes no arguments (contact distances go in pair_coeff)");
}

void PairHardSphere::coeff(int narg, char **arg) {
  if (narg != 2 && narg != 3)
    error->all(FLERR, "pair_coeff for pair_style hardsphere: expected 'pair_coeff I J [diameter]'");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  double d = -1.0;
  if (narg == 3) {
    d = utils::numeric(FLERR, arg[2], false, lmp);
    if (!(d > 0.0))
      error->all(FLERR, std::string("pair_coeff for pair_style hardsphere: diameter ") + arg[2] + " must be positive");
  }
  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = (jlo > i ? jlo : i); j <= jhi; j++) {
      diam[i][j] = d;
      setflag[i][j] = 1;
      count++;
    }
  if (count == 0) error->all(FLERR, "pair_coeff for pair_style hardsphere: no type pair in the given ranges");
}

void PairHardSphere::init_style() {
  if (!atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, "pair_style hardsphere needs per-atom radius and mass: use 'atom_style sphere'");
  if (force->pair != this)
    error->all(FLERR, std::string("pair_style hardsphere cannot be a sub-style of pair_style ") +
                          (force->pair_style ? force->pair_style : "hybrid") +
                          ": fix hardsphere would never apply the other styles' forces; use 'pair_style "
                          "hardsphere' alone");
  // Only a run moves atoms: write_data, balance or velocity also initialise the styles, and the
  // fix may still be defined before the run.
  if (update->whichflag != 0 && !hs_compat::has_fix_style(modify, "^hardsphere$") && !hardsphere_rerun_in_progress(lmp))
    error->all(FLERR,
               "pair_style hardsphere only provides contact distances: add 'fix ID all hardsphere' "
               "to move the atoms (and no other time integrator)");
  // No neighbour list of its own: fix hardsphere requests the one it needs.
  auto_diameter = -1.0;
}

namespace {
// Input keeps the current command's name protected; a member pointer formed in a derived class
// applies to any Input object.
struct InputCommand : Input {
  static char *of(Input *in) { return in->*(&InputCommand::command); }
};
}  // namespace

bool LAMMPS_NS::hardsphere_rerun_in_progress(LAMMPS *lmp) {
  const char *command = lmp->input ? InputCommand::of(lmp->input) : nullptr;
  return lmp->update->whichflag == 1 && command && std::strcmp(command, "rerun") == 0;
}

double PairHardSphere::auto_cut() {
  // Atoms a fix inserts during the run (fix pour, fix deposit) count too.
  double inserted = 0.0;
  for (int t = 1; t <= atom->ntypes; t++) inserted = std::max(inserted, OtherFixes::inserted_radius(modify, t));
  if (atom->natoms == 0 && !(inserted > 0.0)) {
    // LAMMPS initialises the pair style before the fixes: a fix hardsphere cannot follow is the
    // cause to name first.
    for (int i = 0; i < modify->nfix; i++)
      if (auto *fix = dynamic_cast<FixHardSphere *>(modify->fix[i])) fix->check_other_fixes();
    error->all(FLERR,
               "pair_style hardsphere: the box has no atoms ('pair_coeff * *' takes the contact distance from "
               "their diameters); create or read them (create_atoms, read_data) before 'run', or insert them "
               "during it (fix pour, fix deposit)");
  }
  double rmax = inserted;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->radius[i] > rmax) rmax = atom->radius[i];
  double all = 0.0;
  MPI_Allreduce(&rmax, &all, 1, MPI_DOUBLE, MPI_MAX, world);
  if (!(all > 0.0))
    error->all(FLERR,
               "pair_style hardsphere: all atoms have zero radius; set diameters in the data file or with 'set'");
  return 2.0 * all;
}

double PairHardSphere::per_atom_diameter() {
  if (!(auto_diameter > 0.0)) auto_diameter = auto_cut();  // once per init (init_style resets it)
  return auto_diameter;
}

double PairHardSphere::resolved(int i, int j) { return diam[i][j] > 0.0 ? diam[i][j] : per_atom_diameter(); }

double PairHardSphere::init_one(int i, int j) {
  // diam keeps what pair_coeff gave (< 0: the per-atom diameters); cut is what is in use.
  double c = 0.0;
  const std::string ij = std::to_string(i) + " " + std::to_string(j);
  std::string given = "the largest per-atom diameter, pair_coeff * *";  // where c came from, for messages
  if (setflag[i][j]) {
    c = resolved(i, j);
    if (diam[i][j] > 0.0) given = "pair_coeff " + ij;
  } else if (setflag[i][i] && setflag[j][j]) {
    const bool mixed = diam[i][i] > 0.0 && diam[j][j] > 0.0;
    c = mixed ? mix_distance(diam[i][i], diam[j][j]) : per_atom_diameter();
    if (mixed)
      given = "mixed from pair_coeff " + std::to_string(i) + " " + std::to_string(i) + " and " + std::to_string(j) +
              " " + std::to_string(j);
  } else
    error->all(FLERR, "pair_style hardsphere: pair_coeff missing for types " + ij +
                          " (use 'pair_coeff * *' to take the per-atom diameters)");
  // write_data stores only the I I values unless given 'pair ij', and warns when LAMMPS's
  // mixed_flag says that mixing them would not give every I J.
  if (i != j && std::abs(c - mix_distance(resolved(i, i), resolved(j, j))) > 1e-12 * c) mixed_flag = 0;
  check_fits_box(i, j, c, given);
  cut[i][j] = cut[j][i] = c;
  return c;
}

void PairHardSphere::check_fits_box(int i, int j, double c, const std::string &given) {
  // The rule the library applies to the spheres' own diameters (validate_and_wrap): two spheres
  // in contact see one periodic image of each other, and a sphere fits between walls. Checked
  // here, at the first command that sizes anything by the cutoff: LAMMPS copies every atom into
  // each periodic image within the contact distance + skin, without bound.
  const char axis[3] = {'x', 'y', 'z'};
  for (int d = 0; d < 3; d++) {
    const double len = domain->prd[d];
    const bool periodic = domain->periodicity[d] != 0;
    if (periodic ? 2.0 * c <= len : c < len) continue;
    error->all(FLERR,
               "pair_style hardsphere: contact distance " + format_number(c) + " of types " + std::to_string(i) + " " +
                   std::to_string(j) + " (" + given + ") does not fit the box: " +
                   (periodic ? "at most half the periodic box length " + format_number(len) + " along " + axis[d] +
                                   " (spheres in contact see one image of each other)"
                             : "less than the distance " + format_number(len) + " between the walls along " + axis[d]) +
                   "; use a smaller diameter or a larger box");
  }
}

void PairHardSphere::write_restart(FILE *fp) {
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) fwrite(&diam[i][j], sizeof(double), 1, fp);
    }
}

void PairHardSphere::read_restart(FILE *fp) {
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        if (me == 0) utils::sfread(FLERR, &diam[i][j], sizeof(double), 1, fp, nullptr, error);
        MPI_Bcast(&diam[i][j], 1, MPI_DOUBLE, 0, world);
      }
    }
}

void PairHardSphere::write_data(FILE *fp) {
  for (int i = 1; i <= atom->ntypes; i++) fprintf(fp, "%d %.15g\n", i, cut[i][i]);
}

void PairHardSphere::write_data_all(FILE *fp) {
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) fprintf(fp, "%d %d %.15g\n", i, j, cut[i][j]);
}
