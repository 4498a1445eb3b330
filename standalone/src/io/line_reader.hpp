#pragma once
//! Lines and words of a LAMMPS data file, for the reader (data_reader.cpp) and its sections
//! (data_sections.cpp): every refusal is a FormatError naming file:line and the value.
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <string>
#include <vector>

#include "hardsphere/errors.hpp"
#include "hardsphere/limits.hpp"

namespace hardsphere::data {

using Words = std::vector<std::string>;

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

inline Words split(const std::string& line) {
  Words words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

inline std::string strip_comment(const std::string& line) {
  const auto hash = line.find('#');
  return hash == std::string::npos ? line : line.substr(0, hash);
}

inline std::string shown(const std::string& w);

inline std::string join(const Words& w) {
  std::string all;
  for (const auto& x : w) all += (all.empty() ? "" : " ") + x;
  return shown(all);
}

//! Control characters escaped: a NUL from the file would cut the message short.
inline std::string escaped(const std::string& m) {
  std::string out;
  for (const char ch : m) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else {
      out += ch;
    }
  }
  return out;
}

//! A value as messages show it: long words shortened (a 64 KiB "number" is not worth repeating).
inline std::string shown(const std::string& w) { return w.size() > 64 ? w.substr(0, 64) + "..." : w; }

inline bool is_section_name(const std::string& w) {
  static const char* names[] = {"Atoms",
                                "Velocities",
                                "Masses",
                                "Bonds",
                                "Angles",
                                "Dihedrals",
                                "Impropers",
                                "Ellipsoids",
                                "Lines",
                                "Triangles",
                                "Bodies",
                                "Pair",
                                "PairIJ",
                                "Bond",
                                "Angle",
                                "Dihedral",
                                "Improper",
                                "BondBond",
                                "BondAngle",
                                "MiddleBondTorsion",
                                "EndBondTorsion",
                                "AngleTorsion",
                                "AngleAngleTorsion",
                                "BondBond13",
                                "AngleAngle",
                                "Atom"};  // "Atom Type Labels"
  for (const char* n : names)
    if (w == n) return true;
  return false;
}

//! A line that starts a section: a section name alone ("Atoms") or the first word of a
//! coefficient or label section ("Pair Coeffs", "Atom Type Labels").
inline bool is_section_line(const Words& w) {
  return !w.empty() && is_section_name(w[0]) &&
         (w.size() == 1 || (w.size() == 2 && w[1] == "Coeffs") ||
          (w.size() == 3 && w[1] == "Type" && w[2] == "Labels"));
}

class LineReader {
 public:
  LineReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}

  //! The next line without its '\n'; false at end of input. Lines are bounded (kMaxDataLine),
  //! so a file without newlines cannot grow one string without limit.
  bool next(std::string& line) {
    line.clear();
    std::streambuf* buf = in_.rdbuf();
    bool any = false;
    for (;;) {
      const int c = buf ? buf->sbumpc() : std::char_traits<char>::eof();
      if (c == std::char_traits<char>::eof()) break;
      any = true;
      if (c == '\n') break;
      if (line.size() >= kMaxDataLine) {
        ++line_no_;
        fail("line is longer than " + std::to_string(kMaxDataLine) + " characters (not a LAMMPS data file?)");
      }
      line.push_back(char(c));
    }
    if (!any) return false;
    ++line_no_;
    return true;
  }

  //! The next line with words (comments removed); false at end of input.
  bool next_content(Words& words, std::string* raw = nullptr) {
    std::string line;
    while (next(line)) {
      words = split(strip_comment(line));
      if (raw) *raw = line;
      if (!words.empty()) return true;
    }
    return false;
  }

  [[noreturn]] void fail(const std::string& what) const { throw FormatError(name_, line_no_, escaped(what)); }
  //! "<what> [<who>] '<w>' <why>", e.g. "x of atom 7 '1.2.3' is not a number".
  [[noreturn]] void fail_value(const char* what, const std::string* who, const std::string& w,
                               const std::string& why) const {
    fail(std::string(what) + (who ? " " + *who : "") + " '" + shown(w) + "' " + why);
  }

  //! A finite double written as LAMMPS reads numbers (digits, signs, '.' and an exponent only:
  //! no hexadecimal, inf or nan, which LAMMPS refuses, so every file read here reads in LAMMPS).
  //! Values that underflow to a subnormal or zero are what strtod rounds them to (hardsphere
  //! writes subnormals itself); overflow is refused.
  double real(const std::string& w, const char* what, const std::string* who = nullptr) const {
    for (const char c : w)
      if (!((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.' || c == 'e' || c == 'E'))
        fail_value(what, who, w, "is not a number (LAMMPS reads digits, a sign, '.' and an exponent only)");
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(w.c_str(), &end);
    if (w.empty() || end != w.c_str() + w.size()) fail_value(what, who, w, "is not a number");
    if (!std::isfinite(v)) fail_value(what, who, w, errno == ERANGE ? "is too large for a double" : "is not finite");
    return v;
  }

  //! A decimal integer in [lo, hi]; `range` explains the bounds when it is outside.
  //! The message is built only on failure: these run six times per atom.
  std::int64_t integer(const std::string& w, const char* what, std::int64_t lo = LLONG_MIN, std::int64_t hi = LLONG_MAX,
                       const std::string& range = {}, const std::string* who = nullptr) const {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(w.c_str(), &end, 10);
    if (w.empty() || end != w.c_str() + w.size()) fail_value(what, who, w, "is not an integer");
    if (errno == ERANGE || v < lo || v > hi)
      fail_value(what, who, w, range.empty() ? "is out of range" : "is out of range (" + range + ")");
    return v;
  }

  long line() const { return line_no_; }
  const std::string& name() const { return name_; }

 private:
  std::istream& in_;
  std::string name_;
  long line_no_ = 0;
};

// Reads the next row of a section that must have `rows` of them; refuses end of file or a
// section name in its place, naming how many rows came.
inline void next_row(LineReader& r, Words& w, const char* section, std::int64_t k, std::int64_t rows,
                     const char* unit) {
  const std::string count = std::to_string(k) + " of " + std::to_string(rows) + " " + unit;
  if (!r.next_content(w)) r.fail(std::string(section) + " section ends after " + count + " (end of file)");
  if (is_section_line(w))
    r.fail(std::string(section) + " section ends after " + count + ": found section '" + join(w) + "'");
}

}  // namespace hardsphere::data
