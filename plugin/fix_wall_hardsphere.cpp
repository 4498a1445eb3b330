#include "fix_wall_hardsphere.h"

#include <cstring>
#include <string>

#include "error.h"
#include "fix_hardsphere.h"
#include "hardsphere/errors.hpp"
#include "modify.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;

namespace {

const char *const kUsage =
    "use 'fix ID all wall/hardsphere xplane|yplane|zplane LO HI [keywords]' (LO or HI NULL for none) or "
    "'fix ID all wall/hardsphere zcylinder RADIUS [keywords]'; keywords: restitution E, "
    "tangential_restitution B, friction MU, shear x|y|z V, wiggle x|y|z A P, rotate W (zcylinder)";

bool is_plane_style(const std::string &s) { return s == "xplane" || s == "yplane" || s == "zplane"; }

}  // namespace

FixWallHardSphere::FixWallHardSphere(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg) {
  const std::string name = std::string("fix ") + id + " (wall/hardsphere)";
  if (narg < 4) error->all(FLERR, name + ": no wall given; " + kUsage);
  if (igroup != 0)
    error->all(FLERR, name + " acts on group '" + std::string(arg[1]) +
                          "', but every atom of fix hardsphere meets its walls: use group all");
  const std::string style = arg[3];
  // The wall's words in the library's grammar (parse_wall_shape), one spec per surface.
  std::vector<std::string> specs;
  int a = 4;
  if (is_plane_style(style)) {
    if (narg < 6) error->all(FLERR, name + ": " + style + " needs LO and HI (NULL for none); " + kUsage);
    const int d = style[0] - 'x';
    for (int side = 0; side < 2; side++) {
      const std::string at = arg[4 + side];
      if (at == "NULL") continue;
      utils::numeric(FLERR, at.c_str(), false, lmp);  // LAMMPS's own refusal of a non-number
      std::string p[3] = {"0", "0", "0"}, n[3] = {"0", "0", "0"};
      p[d] = at;
      n[d] = side == 0 ? "1" : "-1";  // the lower wall faces up its axis, the upper one down
      specs.push_back("plane " + p[0] + " " + p[1] + " " + p[2] + " " + n[0] + " " + n[1] + " " + n[2]);
    }
    if (specs.empty()) error->all(FLERR, name + ": " + style + " NULL NULL gives no wall");
    a = 6;
  } else if (style == "zcylinder") {
    if (narg < 5) error->all(FLERR, name + ": zcylinder needs its RADIUS; " + kUsage);
    utils::numeric(FLERR, arg[4], false, lmp);
    specs.push_back(std::string("cylinder z 0 0 ") + arg[4] + " inside");  // fix wall/gran's: axis x = y = 0
    a = 5;
  } else {
    error->all(FLERR, name + ": unknown wall style '" + style + "'; " + kUsage +
                          " (regions: boundary f faces, or shapes of the standalone's --wall)");
  }
  std::string keywords;
  bool wiggle = false;
  for (; a < narg; a++) {
    const std::string k = arg[a];
    if (k == "restitution" || k == "tangential_restitution" || k == "friction" || k == "rotate") {
      if (a + 1 >= narg) error->all(FLERR, name + ": keyword '" + k + "' needs a value");
      if (k == "rotate" && style != "zcylinder")
        error->all(FLERR, name + ": 'rotate' turns a zcylinder about its axis; a plane slides with 'shear'");
      keywords += " " + k + " " + arg[a + 1];
      a += 1;
    } else if (k == "shear") {
      if (a + 2 >= narg) error->all(FLERR, name + ": 'shear' needs a direction (x, y or z) and a velocity");
      const std::string dim = arg[a + 1];
      if (dim != "x" && dim != "y" && dim != "z")
        error->all(FLERR, name + ": shear direction '" + dim + "' must be x, y or z");
      if (!is_plane_style(style))
        error->all(FLERR, name + ": 'shear' slides a plane's surface; a zcylinder turns with 'rotate'");
      std::string v[3] = {"0", "0", "0"};
      v[dim[0] - 'x'] = arg[a + 2];
      keywords += " shear " + v[0] + " " + v[1] + " " + v[2];
      a += 2;
    } else if (k == "wiggle") {  // fix wall/gran's: A (1 - cos 2 pi t / P), t from this fix's step
      if (a + 3 >= narg)
        error->all(FLERR, name + ": 'wiggle' needs a direction (x, y or z), an amplitude and a period");
      const std::string dim = arg[a + 1];
      if (dim != "x" && dim != "y" && dim != "z")
        error->all(FLERR, name + ": wiggle direction '" + dim + "' must be x, y or z");
      if (style == "zcylinder" && dim != "z")
        error->all(FLERR, name + ": a zcylinder wiggles along its axis only: use 'wiggle z A P'");
      utils::numeric(FLERR, arg[a + 2], false, lmp);
      utils::numeric(FLERR, arg[a + 3], false, lmp);
      keywords += " wiggle " + dim + " " + arg[a + 2] + " " + arg[a + 3];
      wiggle = true;
      a += 3;
    } else {
      error->all(FLERR, name + ": unknown keyword '" + k + "'; " + kUsage);
    }
  }
  if (wiggle && keywords.find(" shear ") != std::string::npos)
    error->all(FLERR, name + ": 'wiggle' and 'shear' together (fix wall/gran refuses them too): give one");
  // The wall's time is fix wall/gran's: the steps since this fix was defined times dt. Engines
  // are made at a run's setup (the state is at ntimestep) or within a step (at ntimestep - 1).
  time_origin_ = update->ntimestep;
  const auto clock = [this]() {
    const bigint steps = update->ntimestep - time_origin_ - (update->setupflag ? 0 : 1);
    return double(steps) * update->dt;
  };
  for (const std::string &spec : specs) {
    try {
      shapes_.push_back(hardsphere::parse_wall_shape(spec + keywords, name));
      if (wiggle) shapes_.back().clock = clock;
    } catch (const std::exception &e) {
      error->all(FLERR, e.what());
    }
  }
}

void FixWallHardSphere::init() {
  for (int i = 0; i < modify->nfix; i++)
    if (dynamic_cast<FixHardSphere *>(modify->fix[i])) return;
  error->all(FLERR, std::string("fix ") + id +
                        " (wall/hardsphere) is a wall for hard spheres: add 'fix ID all hardsphere', which "
                        "collides the atoms with it");
}
