#pragma once
//! LAMMPS-compatible files: data files (atom_style sphere) in and out, text dumps out.
//! Everything is written to a temporary file and renamed on success, so a failed run never
//! leaves a half-written output behind.
#include <array>
#include <cstdint>
#include <fstream>
#include <string>

#include "hardsphere/particles.hpp"

namespace hardsphere {

//! Reads a LAMMPS data file with an Atoms section in atom_style sphere
//! (id type diameter density x y z [ix iy iz]) and an optional Velocities section
//! (id vx vy vz [wx wy wz]). Mass = density * 4/3 pi r^3, computed as LAMMPS does, so both
//! programs see bit-identical masses. Data files carry no boundary conditions: pass them.
//! Throws FormatError ("file:line: ...") for anything malformed, then validates the state.
ParticleSystem read_data(const std::string& path, std::array<bool, 3> periodic);

//! Writes a LAMMPS data file (atom_style sphere) with full double precision.
void write_data(const std::string& path, const ParticleSystem& sys, const std::string& title);

//! A file written under a temporary name and moved into place by commit().
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  std::ofstream& stream() { return out_; }
  void commit();  //!< flush, check for write errors, rename into place

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

//! LAMMPS text dump ("ITEM: ATOMS id type radius x y z vx vy vz"), readable by OVITO and VMD.
class DumpWriter {
 public:
  explicit DumpWriter(const std::string& path) : file_(path) {}
  void write_frame(std::int64_t timestep, const ParticleSystem& sys);
  void commit() { file_.commit(); }

 private:
  AtomicFile file_;
};

}  // namespace hardsphere
