#pragma once
//! The stepper's cell grid and pair-list skin. A user grid is taken as given. The automatic one
//! starts from the skin auto_skin() tunes for a gas of typical spheres; where a few spheres are
//! far from typical (one much faster, or big ones the box is too short to give a pass of their
//! own) that skin can be so thick that the grid collapses to a few cells, and a model of the
//! step's work picks a thinner one instead.
#include <array>
#include <string>

#include "hardsphere/particles.hpp"
#include "scene/cell_grid.hpp"
#include "scene/size_classes.hpp"

namespace hardsphere::detail {

struct GridChoice {
  CellGrid grid;
  double diameter = 0;    //!< the diameter the cells are sized for (the grid diameter with a big pass)
  bool big_pass = false;  //!< big spheres find their partners in a pass of their own
  double skin = 0;        //!< reach - diameter (+inf: one cell covers a periodic axis); <= 0 is refused
};

//! The skin cells = auto tunes for a gas at packing fraction phi_gas stepped by dt.
double auto_skin(const ParticleSystem& sys, double dt, double phi_gas);

//! The grid for `sys` in the stepper's frame `box` (0 to L): `cells` (all 0 = automatic).
GridChoice choose_grid(const ParticleSystem& sys, const Box& box, const std::array<int, 3>& cells, double dt,
                       double phi_gas, const SizeSplit& split, const std::array<double, 3>& gravity);

//! Why `choice` (skin <= 0) cannot serve `sys`: the box too short for its spheres (the grid is
//! automatic, or a periodic axis has fewer than 3 cells), or the user's cells too narrow.
std::string grid_refusal(const ParticleSystem& sys, const GridChoice& choice, bool auto_cells, const SizeSplit& split);

}  // namespace hardsphere::detail
