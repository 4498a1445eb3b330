#include "register_styles.h"

#include "fix_hardsphere.h"
#include "fix_wall_hardsphere.h"
#include "fix_wall_hardsphere_region.h"
#include "force.h"
#include "lammps.h"
#include "modify.h"
#include "pair_hardsphere.h"

namespace LAMMPS_NS {

namespace {
Fix *create_fix_hardsphere(LAMMPS *lmp, int narg, char **arg) { return new FixHardSphere(lmp, narg, arg); }
Fix *create_fix_wall(LAMMPS *lmp, int narg, char **arg) { return new FixWallHardSphere(lmp, narg, arg); }
Fix *create_fix_wall_region(LAMMPS *lmp, int narg, char **arg) { return new FixWallHardSphereRegion(lmp, narg, arg); }
Pair *create_pair_hardsphere(LAMMPS *lmp) { return new PairHardSphere(lmp); }
}  // namespace

void hardsphere_register_styles(LAMMPS *lmp) {
  (*lmp->modify->fix_map)["hardsphere"] = &create_fix_hardsphere;
  (*lmp->modify->fix_map)["wall/hardsphere"] = &create_fix_wall;
  (*lmp->modify->fix_map)["wall/hardsphere/region"] = &create_fix_wall_region;
  (*lmp->force->pair_map)["hardsphere"] = &create_pair_hardsphere;
}

}  // namespace LAMMPS_NS
