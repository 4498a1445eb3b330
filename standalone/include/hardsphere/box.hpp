#pragma once
//! Simulation box: an axis-aligned cuboid, periodic or bounded by reflecting walls per axis.
#include <array>
#include <string>

namespace hardsphere {

struct Box {
  std::array<double, 3> lo{0, 0, 0};
  std::array<double, 3> hi{1, 1, 1};
  std::array<bool, 3> periodic{true, true, true};

  double length(int d) const { return hi[d] - lo[d]; }
  double volume() const { return length(0) * length(1) * length(2); }
  bool all_periodic() const { return periodic[0] && periodic[1] && periodic[2]; }

  //! Cubic or cuboid box [0,L) with the given boundaries.
  static Box from_lengths(std::array<double, 3> lengths, std::array<bool, 3> periodic);
};

//! Throws InputError unless every length is finite and positive (names `source` in the message).
void validate_box(const Box& box, const std::string& source);

//! "p" or "w" per axis, e.g. "p,p,w" or a single letter for all axes.
std::array<bool, 3> parse_boundary(const std::string& spec);
std::string boundary_string(const std::array<bool, 3>& periodic);  // e.g. "p,p,w"

}  // namespace hardsphere
