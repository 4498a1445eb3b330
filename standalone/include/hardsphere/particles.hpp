#pragma once
//! The canonical particle state exchanged between engines, initialisers and file I/O.
//! Engines keep their own reordered, precision-specific copies; this one is ordered as read.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hardsphere/box.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere {

//! Big spheres, whose partners the engines find in a pass of their own instead of sizing the
//! cell grid by them: a sphere is big when its diameter exceeds this many median diameters ...
constexpr double kBigOverMedian = 2.0;
//! ... and it is among the kMaxBigSpheres largest: big against big is an all-pairs pass.
constexpr std::size_t kMaxBigSpheres = 256;

struct ParticleSystem {
  Box box;
  std::vector<std::int64_t> id;  //!< LAMMPS atom IDs, kept through every engine
  std::vector<int> type;         //!< LAMMPS atom types (>= 1)
  std::vector<double> radius;
  std::vector<double> mass;
  std::vector<Vec3d> pos;
  std::vector<Vec3d> vel;
  //! Periodic images crossed (LAMMPS's image flags): the unwrapped position, continuous in
  //! time, is pos + image * box length per periodic axis. Zero on wall axes.
  std::vector<std::array<std::int32_t, 3>> image;
  //! Angular velocities, same size as pos: rough spheres' change in collisions, smooth spheres
  //! keep theirs.
  std::vector<Vec3d> omega;
  //! Kinematic spheres (1; empty: none): infinite mass and moment of inertia, each moving on its
  //! straight line at its own constant velocity (zero: frozen) and spinning at its constant omega;
  //! no gravity acts on them and collisions never change them. Two kinematic spheres never collide
  //! (they may overlap: a base built on a lattice may touch).
  std::vector<std::uint8_t> kinematic;
  //! Where the spheres were read from, so that every later refusal (an engine's range checks, a
  //! run's work estimate) names "file:line": the file, each sphere's Atoms line and its
  //! Velocities line (0: none), set by read_data; ignored unless there is one line per sphere.
  std::string source;
  std::vector<long> source_line, velocity_line;

  std::size_t size() const { return pos.size(); }
  void resize(std::size_t n);
  void reserve(std::size_t n);
  void push_back(std::int64_t id, int type, double radius, double mass, Vec3d pos, Vec3d vel,
                 std::array<std::int32_t, 3> image = {0, 0, 0}, Vec3d omega = {0, 0, 0});

  bool is_kinematic(std::size_t i) const { return i < kinematic.size() && kinematic[i]; }
  std::size_t kinematic_count() const;
  bool monodisperse() const;  //!< all radii and all masses equal
  double max_radius() const;
  double packing_fraction() const;  //!< sum of sphere volumes / box volume
};

//! Indices that put the ids in ascending order, stable for equal ids (atom tags that span a
//! few times their number are counted into place in O(n)).
std::vector<std::size_t> order_by_id(const std::vector<std::int64_t>& id);

//! One sphere observed at an engine's current time without building the whole state.
struct SphereSample {
  Vec3d unwrapped;  //!< pos + image * box length: continuous in time across periodic faces
  Vec3d velocity;
  //! The sphere's pair collisions since the last reset_counters(); -1 if the engine does not count
  //! them (StepperConfig::count_per_sphere off).
  std::int64_t pair_collisions = 0;
};

//! Full consistency check; throws InputError naming the particle id, the value and `source`:
//! non-positive or non-finite radius/mass, NaN/inf positions, velocities or angular velocities
//! (an omega array shorter than the spheres is filled with zeros), particles outside
//! a wall axis, duplicate ids, periodic box too short for the largest pair, overlapping pairs
//! (two kinematic spheres may overlap; a `kinematic` array of another length is refused).
//! Periodic coordinates are wrapped into the box first (as LAMMPS read_data does).
//! `atom_lines` (optional): the line each atom came from, so messages name "source:line".
//! `rounding_eps` > 0 accepts overlaps, and spheres past a wall, up to overlap_tolerance(sys,
//! rounding_eps): a state an engine of that precision wrote may hold them, and the engines collide
//! such pairs at once. `check_pairs` false leaves pairs to a caller that sees all of them (MPI ranks).
void validate_and_wrap(ParticleSystem& sys, const std::string& source, const std::vector<long>* atom_lines = nullptr,
                       double rounding_eps = 0, bool check_pairs = true);

//! The overlap a few roundings of an engine with machine epsilon `eps` can leave in this scene
//! (coordinates in the engine's type, distances from absolute double coordinates).
double overlap_tolerance(const ParticleSystem& sys, double eps);

//! "source: atom ID" or, with the atom's line known, "source:LINE: atom ID"; without
//! `atom_lines`, the line the system records (source_line) as "source: file:LINE: atom ID".
std::string atom_origin(const ParticleSystem& sys, std::size_t i, const std::string& source,
                        const std::vector<long>* atom_lines);

//! The same for a refusal of the sphere's velocity or angular velocity: its Velocities line when
//! the system records one, else as atom_origin.
std::string velocity_origin(const ParticleSystem& sys, std::size_t i, const std::string& source,
                            const std::vector<long>* atom_lines);

//! Largest pair overlap max(0, R_i + R_j - |r_ij|) over all pairs (minimum image), via a cell grid.
double max_overlap(const ParticleSystem& sys);

//! A pair closer than its contact distance minus `slack` (minimum image).
struct Overlap {
  std::size_t i = 0, j = 0;  //!< indices into the system
  double distance = 0, contact = 0;
};
//! The first overlapping pair a cell pass meets, if any (pairs of kinematic spheres are not overlaps).
std::optional<Overlap> find_overlap(const ParticleSystem& sys, double slack = 0);

//! Wraps periodic coordinates into [lo, hi) and counts the box lengths taken off in `image`
//! (saturating at the int32 range).
void wrap_periodic(ParticleSystem& sys);

}  // namespace hardsphere
