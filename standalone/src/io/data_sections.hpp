#pragma once
//! The sections LAMMPS's write_data puts beside Atoms, Velocities and Masses, so that its files
//! read as they are: coefficient sections (pair_style hardsphere's checked against the atoms,
//! every other style's skipped with a note) and type labels (checked, skipped with a note).
#include <cstdint>
#include <string>
#include <vector>

#include "hardsphere/particles.hpp"
#include "io/line_reader.hpp"

namespace hardsphere::data {

//! The header's type counts: the rows of each type-indexed section.
struct TypeCounts {
  std::int64_t atom = -1, bond = 0, angle = 0, dihedral = 0, improper = 0;
};

class ExtraSections {
 public:
  //! The section a line starts ("Pair Coeffs", "Atom Type Labels", "Atoms") or, for a line that
  //! is none of them, its words.
  static std::string title(const Words& w);
  //! Whether `title` is one of these sections.
  static bool handles(const std::string& title);
  //! Reads the rows of section `title`, whose line was `raw` (its comment names a style).
  void read(LineReader& r, const std::string& title, const std::string& raw, const TypeCounts& counts);
  //! pair_style hardsphere's contact distances must cover the diameters of their types' atoms,
  //! as fix hardsphere requires (LAMMPS's default geometric mixing for types i != j).
  void check(const ParticleSystem& sys, const std::vector<long>& atom_lines, const std::string& file) const;
  //! What was skipped, one note per section ("file:line: ... skipped: why").
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  struct Contact {
    std::int64_t i, j;  // j == 0: a Pair Coeffs row (type i with itself)
    double distance;
    long line;
  };
  std::vector<Contact> contacts_;
  std::vector<std::string> notes_;
};

}  // namespace hardsphere::data
