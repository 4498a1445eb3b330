#pragma once
//! When the other fixes of an input look at or change LAMMPS's x and v: a fix hooked into the
//! step's stages does so every step, one acting only at end_of_step every nevery steps, and a
//! dynamic group's fix (style GROUP: post_integrate in LAMMPS 2021, a post_force list of its own
//! with mask 0 in 2025 and 2026) reads positions every nevery steps. Both paths of fix hardsphere ask
//! this before they read velocities again or write LAMMPS's rows, and the fix asks which of those
//! fixes may also move atoms. Fixes that insert or delete atoms (pour, deposit, evaporate) act in
//! the pre_exchange of the steps they schedule (next_reneighbor): LAMMPS's rows must hold the
//! step's positions for their overlap checks and regions, and the paths take the new set of atoms
//! up after them.
#include <string>
#include <vector>

#include "lmptype.h"

namespace LAMMPS_NS {

class Fix;
class Modify;

class OtherFixes {
 public:
  //! Reads the fixes of `modify` other than `self` (at init).
  void scan(const Modify *modify, const Fix *self);
  //! Whether another fix may have read or changed x and v at the end of `step`.
  bool acted(bigint step) const;
  //! Whether a fix only reads x and v during `step` (a dynamic group updating its members).
  bool reads(bigint step) const;
  //! Whether any other fix acts between steps at all.
  bool any() const { return every_step_ || !every_.empty(); }
  //! Whether another fix that may move atoms acted at the end of `step`.
  bool may_move(bigint step) const { return !movers_.empty() && acted(step); }
  //! Those fixes, for messages: "fix ID (style), ...".
  const std::string &movers() const { return movers_; }
  //! Whether a fix inserts or deletes atoms in `step` (its pre_exchange, after the step's moves).
  bool changes_atoms(bigint step) const;
  //! Whether any fix may insert atoms during a run (a run may then start with none).
  bool inserts() const { return inserts_; }
  //! The fixes that change the atoms in `step`, for messages: "fix ID (style), ...".
  std::string atom_changers(bigint step) const;
  //! fix hardsphere follows these styles' insertions and deletions.
  static bool is_atom_changer(const Fix *f);
  //! The largest radius of the atoms of `type` that fixes of `modify` will insert during a run (fix
  //! pour, fix deposit: their extract("radius", type), as LAMMPS's granular pair styles read it); 0: none.
  static double inserted_radius(const Modify *modify, int type);

 private:
  bool every_step_ = false;   //!< a fix acts inside every step
  std::vector<int> every_;    //!< nevery of the fixes acting only at end_of_step
  std::vector<int> readers_;  //!< nevery of the dynamic groups' fixes
  std::string movers_;
  std::vector<const Fix *> changers_;  //!< fixes that insert or delete atoms
  bool inserts_ = false;
};

}  // namespace LAMMPS_NS
