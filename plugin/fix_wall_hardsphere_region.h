#pragma once
//! `fix ID all wall/hardsphere/region REGION-ID [restitution E] [tangential_restitution B]
//! [friction MU]`: the surface of a LAMMPS region as walls the hard spheres of fix hardsphere
//! collide with (docs/fix_wall_hardsphere.md), in place of fix wall/gran/region's contact force.
//! The region is read into the library's shapes (region_shapes.h: a block's six planes, a
//! cylinder's tube and caps, a cone, a sphere, a plane, a union of these); a region turning
//! ('rotate V_THETA ...') about its own axis turns their surfaces at the rate of its variable,
//! which fix hardsphere sets before each step.
#include <string>
#include <utility>
#include <vector>

#include "fix.h"
#include "region_shapes.h"

namespace LAMMPS_NS {

class FixWallHardSphereRegion : public Fix {
 public:
  FixWallHardSphereRegion(class LAMMPS *lmp, int narg, char **arg);
  int setmask() override { return 0; }
  void init() override;
  //! The region's walls (rotating ones at rest: see rates()), unvalidated: fix hardsphere
  //! validates them with the rest of the physics.
  const std::vector<hardsphere::WallShape> &shapes() const { return walls_.shapes; }
  //! (index into shapes(), angular velocity) of each turning wall over the step being taken.
  std::vector<std::pair<std::size_t, double>> rates() const;

 private:
  std::string region_id_, name_;
  hardsphere::WallLaw law_;
  RegionWalls walls_;
};

}  // namespace LAMMPS_NS
