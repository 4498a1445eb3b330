#include "hardsphere/box.hpp"

#include <cmath>
#include <sstream>

#include "hardsphere/errors.hpp"

namespace hardsphere {

Box Box::from_lengths(std::array<double, 3> lengths, std::array<bool, 3> periodic) {
  Box b;
  for (int d = 0; d < 3; ++d) {
    b.lo[d] = 0;
    b.hi[d] = lengths[d];
  }
  b.periodic = periodic;
  return b;
}

void validate_box(const Box& box, const std::string& source) {
  static const char* axis = "xyz";
  for (int d = 0; d < 3; ++d) {
    if (!std::isfinite(box.lo[d]) || !std::isfinite(box.hi[d]) || !std::isfinite(box.length(d)) ||
        !(box.length(d) > 0)) {
      std::ostringstream m;
      m << source << ": box " << axis[d] << " extent [" << box.lo[d] << ", " << box.hi[d]
        << "] must be finite with a finite positive length";
      throw InputError(m.str());
    }
  }
}

std::array<bool, 3> parse_boundary(const std::string& spec) {
  std::array<bool, 3> out{};
  std::string s;
  for (char c : spec)
    if (c != ',' && c != ' ') s += c;
  if (s.size() == 1) s = std::string(3, s[0]);
  if (s.size() != 3)
    throw InputError("boundary '" + spec + "' must be one letter or three (p = periodic, w = wall), e.g. p,p,w");
  for (int d = 0; d < 3; ++d) {
    if (s[d] == 'p')
      out[d] = true;
    else if (s[d] == 'w' || s[d] == 'f')
      out[d] = false;
    else
      throw InputError("boundary '" + spec + "': '" + std::string(1, s[d]) + "' is neither p (periodic) nor w (wall)");
  }
  return out;
}

std::string boundary_string(const std::array<bool, 3>& periodic) {
  std::string s;
  for (int d = 0; d < 3; ++d) {
    if (d) s += ',';
    s += periodic[d] ? 'p' : 'w';
  }
  return s;
}

}  // namespace hardsphere
