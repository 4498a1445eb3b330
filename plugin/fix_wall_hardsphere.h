#pragma once
//! `fix ID group wall/hardsphere wallstyle args keyword value ...`: a wall the hard spheres of
//! `fix hardsphere` collide with, in the geometry of `fix wall/gran` (xplane, yplane, zplane,
//! zcylinder; `wiggle dim A P` as fix wall/gran moves it) and with the hard-sphere wall law (restitution,
//! tangential_restitution, friction) instead of a contact force. The fix itself does nothing in a step: fix hardsphere
//! reads its walls at each run's setup and the stepper detects and collides with them (wall_shapes.hpp).
#include <string>
#include <vector>

#include "fix.h"
#include "hardsphere/wall_shapes.hpp"

namespace LAMMPS_NS {

class FixWallHardSphere : public Fix {
 public:
  FixWallHardSphere(class LAMMPS *lmp, int narg, char **arg);
  int setmask() override { return 0; }
  void init() override;
  //! The walls this fix stands for (one or two planes, or a cylinder), unvalidated: fix
  //! hardsphere validates them against the box with the rest of the physics.
  const std::vector<hardsphere::WallShape> &shapes() const { return shapes_; }

 private:
  std::vector<hardsphere::WallShape> shapes_;
  bigint time_origin_ = 0;  //!< the step this fix was defined at: a wiggle's time 0 (fix wall/gran's)
};

}  // namespace LAMMPS_NS
