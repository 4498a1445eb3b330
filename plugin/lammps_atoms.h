#pragma once
//! How LAMMPS's atoms become the kernel's ParticleSystem: the one builder every path uses
//! (the serial path's stepper, the owned + ghost path's checks, its per-rank stepper and its
//! all-atoms re-run). Fields: tag, type, radius, rmass, x, v, and omega for rough spheres.
#include <cstdint>
#include <functional>
#include <vector>

#include "hardsphere/particles.hpp"
#include "pointers.h"

namespace LAMMPS_NS {

//! LAMMPS's global box, its bounds and periodicity.
hardsphere::Box lammps_box(const Domain *domain);

//! Which rows the ParticleSystem holds, and how.
struct AtomRows {
  bool ghosts = false;  //!< owned rows only, or owned rows then ghost rows
  bool rough = false;   //!< omega read (rough spheres); zero otherwise
  //! Group bits of the atoms that are kinematic spheres (fix freeze groups); 0: none.
  int kinematic_bits = 0;
  //! Optional, for row i: whether it is held, and its position and id (given x and the tag;
  //! `so_far` holds the rows taken before). Without it every row is held at x with its tag.
  std::function<bool(int i, const hardsphere::ParticleSystem &so_far, hardsphere::Vec3d &pos, std::int64_t &id)> place;
};

//! The atoms of `rows` in `box`, in row order.
hardsphere::ParticleSystem atoms_to_system(const Atom *atom, const hardsphere::Box &box, const AtomRows &rows);

//! The same fields as flat records of doubles (for MPI gathers): the owned rows, and a system in
//! `box` from any ranks' records.
int atom_record_size(bool rough);
std::vector<double> owned_atom_records(const Atom *atom, bool rough);
hardsphere::ParticleSystem records_to_system(const std::vector<double> &records, const hardsphere::Box &box,
                                             bool rough);

}  // namespace LAMMPS_NS
