// Plugin entry for LAMMPS builds with the PLUGIN package: `plugin load hardsphereplugin.so`.
#include "fix_hardsphere.h"
#include "fix_wall_hardsphere.h"
#include "fix_wall_hardsphere_region.h"
#include "lammps_compat.h"
#include "lammpsplugin.h"
#include "pair_hardsphere.h"
#include "version.h"

using namespace LAMMPS_NS;

namespace {
void *make_pair(void *lmp) { return new PairHardSphere(static_cast<LAMMPS *>(lmp)); }
void *make_fix(void *lmp, int narg, char **arg) { return new FixHardSphere(static_cast<LAMMPS *>(lmp), narg, arg); }
void *make_wall(void *lmp, int narg, char **arg) {
  return new FixWallHardSphere(static_cast<LAMMPS *>(lmp), narg, arg);
}
void *make_wall_region(void *lmp, int narg, char **arg) {
  return new FixWallHardSphereRegion(static_cast<LAMMPS *>(lmp), narg, arg);
}
}  // namespace

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc) {
  hs_compat::check_loaded_into(static_cast<LAMMPS *>(lmp));
  auto reg = (lammpsplugin_regfunc)regfunc;
  lammpsplugin_t p;
  p.version = LAMMPS_VERSION;
  p.author = "hardsphere project";
  p.handle = handle;

  p.style = "pair";
  p.name = "hardsphere";
  p.info = "hard-sphere contact distances and neighbour cutoff (use with fix hardsphere)";
  p.creator.v1 = (lammpsplugin_factory1 *)&make_pair;
  (*reg)(&p, lmp);

  p.style = "fix";
  p.name = "hardsphere";
  p.info = "hard-sphere time stepper: drift and time-ordered elastic collisions";
  p.creator.v2 = (lammpsplugin_factory2 *)&make_fix;
  (*reg)(&p, lmp);

  p.name = "wall/hardsphere";
  p.info = "a wall (plane or cylinder) the atoms of fix hardsphere collide with";
  p.creator.v2 = (lammpsplugin_factory2 *)&make_wall;
  (*reg)(&p, lmp);

  p.name = "wall/hardsphere/region";
  p.info = "the surface of a region (block, cylinder, cone, sphere, plane, union) as walls of fix hardsphere";
  p.creator.v2 = (lammpsplugin_factory2 *)&make_wall_region;
  (*reg)(&p, lmp);
}
