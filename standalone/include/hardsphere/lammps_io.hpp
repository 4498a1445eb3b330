#pragma once
//! LAMMPS-compatible files: data files (atom_style sphere) in and out, text dumps out.
//! Outputs go through AtomicFile, so a failed or interrupted run never leaves a half-written
//! file behind.
#include <array>
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "hardsphere/atomic_file.hpp"
#include "hardsphere/particles.hpp"

namespace hardsphere {

//! Reads a LAMMPS data file with an Atoms section in atom_style sphere
//! (id type diameter density x y z [ix iy iz]) and optional Velocities (id vx vy vz [wx wy wz])
//! and Masses (type mass, not used) sections, and every other section LAMMPS's write_data
//! writes for it: Pair Coeffs / PairIJ Coeffs of pair_style hardsphere (checked: each contact
//! distance covers its types' diameters, as fix hardsphere requires), other coefficient and
//! type label sections (rows checked, then skipped with a note in `notes`), the header's zero
//! topology counts and all-zero tilt factors. Mass = density * 4/3 pi r^3, computed as LAMMPS
//! does, so both programs see bit-identical masses. Data files carry no boundary conditions:
//! pass them. Throws FormatError ("file:line: ...") for anything malformed (repeated header
//! lines or sections, counts out of range, missing or duplicate rows, non-numbers, image flags
//! outside int32, spheres outside a wall, a triclinic box), then validates the whole state
//! (validate_and_wrap, overlaps up to the rounding of an engine with machine epsilon
//! `rounding_eps` accepted). The state records the file and each sphere's lines
//! (ParticleSystem::source). `check_pairs` false leaves the overlap check to a caller that marks
//! kinematic spheres first (they may overlap each other).
ParticleSystem read_data(const std::string& path, std::array<bool, 3> periodic, double rounding_eps = 0,
                         std::vector<std::string>* notes = nullptr, bool check_pairs = true);

//! The same from a stream; `name` stands for the file in messages.
ParticleSystem read_data(std::istream& in, const std::string& name, std::array<bool, 3> periodic,
                         double rounding_eps = 0, std::vector<std::string>* notes = nullptr, bool check_pairs = true);

//! Writes a LAMMPS data file (atom_style sphere) with full double precision (17 digits, so
//! read_data gives back the same state bit for bit), angular velocities included.
void write_data(const std::string& path, const ParticleSystem& sys, const std::string& title);
void write_data(std::ostream& out, const ParticleSystem& sys, const std::string& title);

//! LAMMPS text dump ("ITEM: ATOMS id type radius x y z vx vy vz ix iy iz", then "wx wy wz" for
//! rough spheres, or when the first frame has a spin that is not +0), readable by OVITO and VMD.
class DumpWriter {
 public:
  explicit DumpWriter(const std::string& path, bool omega = false) : file_(path), omega_(omega) {}
  void write_frame(std::int64_t timestep, const ParticleSystem& sys);
  //! Whether the frames carry wx wy wz (set before the first frame; off, the first frame's spins
  //! decide).
  void set_omega(bool on) { omega_ = on; }
  void commit() { file_.commit(); }
  AtomicFile& file() { return file_; }

 private:
  AtomicFile file_;
  bool omega_ = false;
  std::int64_t frames_ = 0;
};

}  // namespace hardsphere
