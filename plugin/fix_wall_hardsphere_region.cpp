#include "fix_wall_hardsphere_region.h"

#include <string>

#include "error.h"
#include "fix_hardsphere.h"
#include "modify.h"
#include "utils.h"

using namespace LAMMPS_NS;

namespace {
const char *const kUsage =
    "use 'fix ID all wall/hardsphere/region REGION-ID [restitution E] [tangential_restitution B] [friction MU]'";
}  // namespace

FixWallHardSphereRegion::FixWallHardSphereRegion(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  name_ = std::string("fix ") + id + " (wall/hardsphere/region)";
  if (narg < 4) error->all(FLERR, name_ + ": no region given; " + kUsage);
  if (igroup != 0)
    error->all(FLERR, name_ + " acts on group '" + std::string(arg[1]) +
                          "', but every atom of fix hardsphere meets its walls: use group all");
  region_id_ = arg[3];
  for (int a = 4; a < narg; a += 2) {
    const std::string k = arg[a];
    if (k != "restitution" && k != "tangential_restitution" && k != "friction") {
      if (k == "wiggle" || k == "shear" || k == "contacts" || k == "temperature")
        error->all(FLERR, name_ + ": keyword '" + k +
                              "' is fix wall/gran/region's, which this fix does not take: a region moves with its "
                              "own 'rotate' (about its own axis); " +
                              kUsage);
      error->all(FLERR, name_ + ": unknown keyword '" + k + "'; " + kUsage);
    }
    if (a + 1 >= narg) error->all(FLERR, name_ + ": keyword '" + k + "' needs a value");
    const double v = utils::numeric(FLERR, arg[a + 1], false, lmp);
    if (k == "restitution")
      law_.restitution = v;
    else if (k == "tangential_restitution")
      law_.tangential_restitution = v;
    else
      law_.friction = v;
  }
  walls_ = region_walls(lmp, region_id_, law_, name_);
}

void FixWallHardSphereRegion::init() {
  bool hard = false;
  for (int i = 0; i < modify->nfix; i++) hard = hard || dynamic_cast<FixHardSphere *>(modify->fix[i]) != nullptr;
  if (!hard)
    error->all(FLERR, name_ +
                          " is a wall for hard spheres: add 'fix ID all hardsphere', which collides the atoms "
                          "with it");
  // The region may have been deleted and defined again since (same ID): read it again.
  walls_ = region_walls(lmp, region_id_, law_, name_);
}

std::vector<std::pair<std::size_t, double>> FixWallHardSphereRegion::rates() const {
  std::vector<std::pair<std::size_t, double>> out;
  for (const RegionTurn &t : walls_.turns) {
    const double rate = region_turn_rate(lmp, t.region);
    for (std::size_t k = 0; k < t.shapes.size(); k++) out.emplace_back(t.shapes[k], rate * t.scales[k]);
  }
  return out;
}
