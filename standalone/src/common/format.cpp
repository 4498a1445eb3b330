#include "hardsphere/format.hpp"

#include <charconv>
#include <cstdio>

namespace hardsphere {

std::string format_number(double x, int digits) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.*g", digits, x);
  return b;
}

std::string format_exact(double x) {
  char b[64];
  const auto end = std::to_chars(b, b + sizeof(b), x).ptr;
  return std::string(b, end);
}

}  // namespace hardsphere
