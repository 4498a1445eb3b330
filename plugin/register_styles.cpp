#include "register_styles.h"

#include "fix_hardsphere.h"
#include "force.h"
#include "lammps.h"
#include "modify.h"
#include "pair_hardsphere.h"

namespace LAMMPS_NS {

namespace {
Fix *create_fix_hardsphere(LAMMPS *lmp, int narg, char **arg) { return new FixHardSphere(lmp, narg, arg); }
Pair *create_pair_hardsphere(LAMMPS *lmp) { return new PairHardSphere(lmp); }
}  // namespace

void hardsphere_register_styles(LAMMPS *lmp) {
  (*lmp->modify->fix_map)["hardsphere"] = &create_fix_hardsphere;
  (*lmp->force->pair_map)["hardsphere"] = &create_pair_hardsphere;
}

}  // namespace LAMMPS_NS
