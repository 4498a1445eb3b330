#pragma once
//! A LAMMPS region's surface as hard-sphere walls (wall_shapes.hpp), for fix
//! wall/hardsphere/region. LAMMPS keeps each region style's parameters private and their layout
//! differs between releases, so the geometry is read through the public API that every tested
//! release has: the region's own inside() test, bisected along coordinate lines from a point
//! inside it, gives each flat face's coordinate exactly and each centre and radius to rounding;
//! the rebuilt solid is then checked against inside() at many random points and refused on any
//! disagreement. A rotating region's axis and point are LAMMPS's own (set_velocity()'s omega and
//! rpoint); its angle comes from its variable through pretransform(). What cannot be followed
//! exactly is refused (error->all) naming the region and what to use.
#include <cstddef>
#include <string>
#include <vector>

#include "hardsphere/wall_shapes.hpp"

namespace LAMMPS_NS {

class LAMMPS;
class Region;

//! A rotating region's walls: LAMMPS turns it by the angle of its variable; each wall's angular
//! velocity (WallShape::omega) is `scale` times the angle's rate.
struct RegionTurn {
  Region *region = nullptr;
  std::vector<std::size_t> shapes;  //!< indices into RegionWalls::shapes
  std::vector<double> scales;       //!< per shape: the axis's signed length along the wall's own axis
};

struct RegionWalls {
  std::vector<hardsphere::WallShape> shapes;  //!< omega 0: the rates are set before each step
  std::vector<RegionTurn> turns;
};

//! The walls of region `id` (its surface, spheres on its `side`), each with `law` and named
//! `name`. Refuses (error->all) what it cannot follow.
RegionWalls region_walls(LAMMPS *lmp, const std::string &id, const hardsphere::WallLaw &law, const std::string &name);

//! The angle's rate of a rotating region over the step being taken (update->ntimestep, from the
//! step before): its variable evaluated at both steps' times, the change LAMMPS's region takes
//! for its velocity at the end of that step (Region::set_velocity()).
double region_turn_rate(LAMMPS *lmp, Region *region);

}  // namespace LAMMPS_NS
