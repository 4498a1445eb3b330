// LAMMPS data files (atom_style sphere) in: every header line, section and row is checked where
// it is read, so each refusal names the value and its file:line. Whole-system checks (overlaps,
// a periodic box too short) follow in validate_and_wrap.
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "hardsphere/errors.hpp"
#include "hardsphere/format.hpp"
#include "hardsphere/lammps_io.hpp"
#include "hardsphere/limits.hpp"
#include "io/data_sections.hpp"
#include "io/line_reader.hpp"

namespace hardsphere {

namespace {

using namespace data;

struct Header {
  std::int64_t natoms = -1, ntypes = -1;
  TypeCounts types;  // every type count, for the coefficient and label sections
  Box box;
  bool have_box[3] = {false, false, false};
  long box_line[3] = {0, 0, 0};
};

// Header lines up to the first section name: "N atoms", "N atom types", "lo hi xlo xhi", ...
// Returns false if the file ends without a section.
bool read_header(LineReader& r, Header& h, Words& w, std::string& raw) {
  std::map<std::string, long> seen;  // keyword -> line, so a repeated line is refused
  auto once = [&](const std::string& key) {
    const auto [it, fresh] = seen.emplace(key, r.line());
    if (!fresh) r.fail("header line '" + key + "' appears twice (first at line " + std::to_string(it->second) + ")");
  };
  bool have_section = r.next_content(w, &raw);
  while (have_section && !is_section_name(w[0])) {
    if (w.size() == 2 && w[1] == "atoms") {
      once("atoms");
      h.natoms = r.integer(w[0], "atom count", 1, kMaxSpheres,
                           "1 to " + std::to_string(kMaxSpheres) + ", the largest system hardsphere simulates");
    } else if (w.size() == 3 && w[1] == "atom" && w[2] == "types") {
      once("atom types");
      h.ntypes = r.integer(w[0], "atom type count", 1, INT_MAX, "1 to " + std::to_string(INT_MAX));
    } else if (w.size() == 4 && (w[2] == "xlo" || w[2] == "ylo" || w[2] == "zlo")) {
      const char axis = w[2][0];
      const int d = axis - 'x';
      if (w[3] != std::string(1, axis) + "hi") r.fail("expected '" + std::string(1, axis) + "hi' after '" + w[2] + "'");
      once(w[2] + " " + w[3]);
      const double lo = r.real(w[0], "box lower bound"), hi = r.real(w[1], "box upper bound");
      if (!(hi > lo)) r.fail("box " + w[2] + " " + w[3] + " is empty: " + w[0] + " >= " + w[1]);
      if (!std::isfinite(hi - lo))
        r.fail("box " + w[2] + " " + w[3] + " length " + w[0] + " .. " + w[1] + " overflows a double");
      h.box.lo[d] = lo;
      h.box.hi[d] = hi;
      h.have_box[d] = true;
      h.box_line[d] = r.line();
    } else if (w.size() == 6 && w[3] == "xy" && w[4] == "xz" && w[5] == "yz") {
      // LAMMPS writes the tilt factors of a box made triclinic; all zero, it is orthogonal.
      once("xy xz yz");
      for (int k = 0; k < 3; ++k)
        if (r.real(w[std::size_t(k)], "tilt factor") != 0)
          r.fail("triclinic box (tilt factors xy xz yz = " + join({w[0], w[1], w[2]}) +
                 ") is not supported: hardsphere simulates orthogonal boxes");
    } else if ((w.size() == 4 && (w[3] == "avec" || w[3] == "bvec" || w[3] == "cvec")) ||
               (w.size() == 5 && w[3] == "abc" && w[4] == "origin")) {
      r.fail("general triclinic box ('" + join(w) + "') is not supported: hardsphere simulates orthogonal boxes");
    } else if (w.size() == 2 && (w[1] == "bonds" || w[1] == "angles" || w[1] == "dihedrals" || w[1] == "impropers" ||
                                 w[1] == "ellipsoids" || w[1] == "lines" || w[1] == "triangles" || w[1] == "bodies" ||
                                 w[1] == "crossterms")) {
      once(w[1]);
      if (r.integer(w[0], "count", 0) != 0)
        r.fail(w[0] + " " + w[1] +
               " are not supported: hardsphere simulates atom_style sphere (no topology, no "
               "other particle shapes)");
    } else if (w.size() == 3 && w[2] == "types" &&
               (w[1] == "bond" || w[1] == "angle" || w[1] == "dihedral" || w[1] == "improper")) {
      once(w[1] + " types");
      // Harmless without bonds (LAMMPS writes them for a hybrid style), but a count.
      const std::int64_t n = r.integer(w[0], "topology type count", 0, INT_MAX, "0 to " + std::to_string(INT_MAX));
      (w[1] == "bond"       ? h.types.bond
       : w[1] == "angle"    ? h.types.angle
       : w[1] == "dihedral" ? h.types.dihedral
                            : h.types.improper) = n;
    } else if (w.size() == 5 && w[1] == "extra" && w[3] == "per" && w[4] == "atom") {
      // "N extra bond per atom" and the like: room LAMMPS reserves for bonds made later.
      once(w[2] + " per atom");
      r.integer(w[0], "extra count", 0);
    } else {
      r.fail("unknown header line '" + join(w) + "'");
    }
    have_section = r.next_content(w, &raw);
  }
  if (h.natoms < 0) r.fail("header has no 'N atoms' line");
  if (h.ntypes < 0) r.fail("header has no 'N atom types' line");
  h.types.atom = h.ntypes;
  for (int d = 0; d < 3; ++d)
    if (!h.have_box[d]) r.fail(std::string("header has no '") + char('x' + d) + "lo " + char('x' + d) + "hi' line");
  return have_section;
}

class DataFile {
 public:
  DataFile(LineReader& r, const Header& h, std::array<bool, 3> periodic)
      : r_(r), h_(h), type_range_("1.." + std::to_string(h.ntypes) + " from the header") {
    sys_.box = h.box;
    sys_.box.periodic = periodic;
    // Never trust a header count for allocation: a lying header must not reserve gigabytes.
    const std::size_t guess = std::size_t(std::min<std::int64_t>(h.natoms, 1 << 20));
    sys_.reserve(guess);
    atom_line_.reserve(guess);
    index_.reserve(guess);
  }

  void atoms(const std::string& raw) {
    // The optional style hint ("Atoms # sphere") must say sphere if present.
    const auto hash = raw.find('#');
    if (hash != std::string::npos) {
      const auto hint = split(raw.substr(hash + 1));
      if (!hint.empty() && hint[0] != "sphere")
        r_.fail("Atoms section is for atom_style '" + hint[0] + "'; hardsphere reads atom_style sphere");
    }
    Words w;
    for (std::int64_t k = 0; k < h_.natoms; ++k) {
      next_row(r_, w, "Atoms", k, h_.natoms, "atoms");
      atom_row(w);
    }
  }

  void velocities() {
    std::vector<long> given(sys_.size(), 0);  // line of each atom's velocity row, 0 = none yet
    Words w;
    for (std::int64_t k = 0; k < h_.natoms; ++k) {
      next_row(r_, w, "Velocities", k, h_.natoms, "atoms");
      if (w.size() != 4 && w.size() != 7)
        r_.fail("velocity line has " + std::to_string(w.size()) + " columns; expected id vx vy vz [wx wy wz]");
      const std::int64_t id = r_.integer(w[0], "atom id");
      const auto it = index_.find(id);
      if (it == index_.end()) r_.fail("velocity for unknown atom id " + w[0]);
      if (given[it->second])
        r_.fail("velocity for atom id " + w[0] + " given twice (first at line " + std::to_string(given[it->second]) +
                ")");
      given[it->second] = r_.line();
      const Vec3d v{r_.real(w[1], "vx of atom", &w[0]), r_.real(w[2], "vy of atom", &w[0]),
                    r_.real(w[3], "vz of atom", &w[0])};
      sys_.vel[it->second] = v;
      if (w.size() == 7) {
        sys_.omega.resize(sys_.size());
        sys_.omega[it->second] = {r_.real(w[4], "angular velocity wx of atom", &w[0]),
                                  r_.real(w[5], "angular velocity wy of atom", &w[0]),
                                  r_.real(w[6], "angular velocity wz of atom", &w[0])};
      }
    }
    // natoms distinct known ids cover every atom; kept as a guard against a future change above.
    const auto missing = std::find(given.begin(), given.end(), 0L);
    if (missing != given.end())
      r_.fail("Velocities section has no row for atom id " + std::to_string(sys_.id[missing - given.begin()]));
    velocity_line_ = std::move(given);
  }

  // Per-type masses are not used (atom_style sphere takes mass from per-atom density; LAMMPS
  // refuses the section for it), but the rows must still be well-formed: `type mass`, each type
  // 1..ntypes once, mass positive; the section is skipped with a note.
  void masses() {
    notes_.push_back(r_.name() + ":" + std::to_string(r_.line()) +
                     ": Masses skipped: atom_style sphere takes each atom's mass from its density (LAMMPS refuses "
                     "per-type masses for it)");
    std::unordered_map<std::int64_t, long> seen;
    Words w;
    for (std::int64_t k = 0; k < h_.ntypes; ++k) {
      next_row(r_, w, "Masses", k, h_.ntypes, "atom types");
      if (w.size() != 2) r_.fail("mass line has " + std::to_string(w.size()) + " columns; expected 'type mass'");
      const std::int64_t type =
          r_.integer(w[0], "atom type", 1, h_.ntypes, "the header has " + std::to_string(h_.ntypes) + " atom types");
      const auto [it, fresh] = seen.emplace(type, r_.line());
      if (!fresh)
        r_.fail("mass of atom type " + w[0] + " given twice (first at line " + std::to_string(it->second) + ")");
      if (!(r_.real(w[1], "mass of atom type", &w[0]) > 0))
        r_.fail("mass " + w[1] + " of atom type " + w[0] + " must be positive");
    }
  }

  //! A periodic axis shorter than two largest diameters makes the minimum image ambiguous;
  //! checked here (validate_and_wrap checks it too) so the message names both lines.
  void check_periodic_lengths() const {
    static const char* axis = "xyz";
    for (int d = 0; d < 3; ++d) {
      if (!sys_.box.periodic[d] || !(sys_.box.length(d) < 4 * max_radius_)) continue;
      throw FormatError(r_.name(), h_.box_line[d],
                        std::string("periodic box length ") + format_number(sys_.box.length(d), 17) + " along " +
                            axis[d] + " is less than twice the largest diameter " + format_number(2 * max_radius_, 17) +
                            " (atom " + std::to_string(sys_.id[widest_]) + ", line " +
                            std::to_string(atom_line_[widest_]) + "): the minimum image would be ambiguous");
    }
  }

  ParticleSystem take() { return std::move(sys_); }
  const ParticleSystem& system() const { return sys_; }
  const std::vector<long>& atom_lines() const { return atom_line_; }
  //! Each atom's Velocities line (empty without that section).
  const std::vector<long>& velocity_lines() const { return velocity_line_; }
  //! What was read and not used: a Masses section, image flags on wall axes.
  std::vector<std::string> notes() const {
    std::vector<std::string> out = notes_;
    if (wall_images_ > 0)
      out.push_back(first_wall_image_ +
                    (wall_images_ > 1 ? " and " + std::to_string(wall_images_ - 1) + " more on wall axes" : "") +
                    " set to 0, as LAMMPS does: a wall axis has no periodic images");
    return out;
  }

 private:
  void atom_row(const Words& w) {
    if (w.size() != 7 && w.size() != 10)
      r_.fail("atom line has " + std::to_string(w.size()) +
              " columns; atom_style sphere needs 7 (id type diameter density x y z) or 10 (with image flags)");
    const std::string& id_s = w[0];
    const std::int64_t id = r_.integer(id_s, "atom id", 1, LLONG_MAX, "ids are >= 1");
    const auto [it, fresh] = index_.emplace(id, sys_.size());
    if (!fresh)
      r_.fail("atom id " + id_s + " appears twice (first at line " + std::to_string(atom_line_[it->second]) + ")");
    const std::int64_t type = r_.integer(w[1], "atom type", 1, h_.ntypes, type_range_);
    const double diameter = r_.real(w[2], "diameter of atom", &id_s);
    const double density = r_.real(w[3], "density of atom", &id_s);
    if (!(diameter > 0))
      r_.fail("diameter " + w[2] + " of atom " + id_s + " must be positive (hard spheres have size)");
    if (!(density > 0)) r_.fail("density " + w[3] + " of atom " + id_s + " must be positive");
    const Vec3d p{r_.real(w[4], "x of atom", &id_s), r_.real(w[5], "y of atom", &id_s),
                  r_.real(w[6], "z of atom", &id_s)};
    // Image flags: kept, so unwrapped positions continue from the file's.
    std::array<std::int32_t, 3> image{0, 0, 0};
    for (std::size_t c = 7; c < w.size(); ++c)
      image[c - 7] =
          std::int32_t(r_.integer(w[c], "image flag of atom", INT32_MIN, INT32_MAX, "32-bit integers", &id_s));
    const double radius = 0.5 * diameter;
    // Same operation order as LAMMPS AtomVecSphere, so masses agree to the last bit.
    const double mass = density * (4.0 * M_PI / 3.0 * radius * radius * radius);
    if (!(radius > 0 && std::isfinite(mass) && mass > 0))
      r_.fail("atom " + id_s + " with diameter " + w[2] + " and density " + w[3] + " has mass " +
              format_number(mass, 17) + ", not a positive finite number");
    if (radius > max_radius_) {
      max_radius_ = radius;
      widest_ = sys_.size();
    }
    atom_line_.push_back(r_.line());
    for (int d = 0; d < 3; ++d)  // walls: no images; reset with a note, as LAMMPS does
      if (!sys_.box.periodic[d] && image[std::size_t(d)] != 0) {
        if (wall_images_++ == 0)
          first_wall_image_ = r_.name() + ":" + std::to_string(r_.line()) + ": atom " + id_s + ": image flag " +
                              w[7 + std::size_t(d)] + " on the wall axis " + "xyz"[d];
        image[std::size_t(d)] = 0;
      }
    sys_.push_back(id, int(type), radius, mass, p, {}, image);
  }

  LineReader& r_;
  const Header& h_;
  const std::string type_range_;  // for messages, built once
  ParticleSystem sys_;
  std::unordered_map<std::int64_t, std::size_t> index_;  // atom id -> row
  std::vector<long> atom_line_, velocity_line_;
  std::vector<std::string> notes_;
  std::int64_t wall_images_ = 0;  // image flags on wall axes reset to 0, the first of them named
  std::string first_wall_image_;
  double max_radius_ = 0;
  std::size_t widest_ = 0;  // row of the largest sphere
};

}  // namespace

ParticleSystem read_data(std::istream& in, const std::string& name, std::array<bool, 3> periodic, double rounding_eps,
                         std::vector<std::string>* notes, bool check_pairs) {
  LineReader r(in, name);
  std::string line;
  if (!r.next(line)) throw InputError(name + ": empty file (a LAMMPS data file starts with a title line)");
  Header h;
  Words w;
  std::string raw;
  bool have_section = read_header(r, h, w, raw);
  DataFile data(r, h, periodic);
  ExtraSections extra;
  std::map<std::string, long> seen;  // section -> line, so a repeated section is refused
  while (have_section) {
    const std::string name_w = ExtraSections::title(w);
    const bool ours = name_w == "Atoms" || name_w == "Velocities" || name_w == "Masses";
    if (!ours && !ExtraSections::handles(name_w)) {
      if (w.size() > 1 && (w[0] == "Atoms" || w[0] == "Velocities" || w[0] == "Masses"))
        r.fail("unexpected '" + w[1] + "' after section name '" + w[0] + "' (a style hint goes in a comment: '" + w[0] +
               " # sphere')");
      r.fail("section '" + name_w +
             "' is not supported (atom_style sphere needs Atoms and optional Velocities, Masses; coefficient and "
             "type label sections are read too)");
    }
    const auto [it, fresh] = seen.emplace(name_w, r.line());
    if (!fresh) r.fail("second " + name_w + " section (first at line " + std::to_string(it->second) + ")");
    std::string unit = "atoms";
    if (name_w == "Atoms") {
      data.atoms(raw);
    } else if (name_w == "Velocities") {
      if (!seen.count("Atoms")) r.fail("Velocities section before Atoms section");
      data.velocities();
    } else if (name_w == "Masses") {
      data.masses();
      unit = "atom types";
    } else {
      extra.read(r, name_w, raw, h.types);
      unit = "rows of " + name_w;
    }
    have_section = r.next_content(w, &raw);
    if (have_section && !is_section_name(w[0]))
      r.fail("expected a section name, found '" + join(w) + "' (more rows than the header's " + unit + "?)");
  }
  if (!seen.count("Atoms")) r.fail("no Atoms section");
  data.check_periodic_lengths();
  extra.check(data.system(), data.atom_lines(), name);
  if (notes) {
    notes->insert(notes->end(), extra.notes().begin(), extra.notes().end());
    const std::vector<std::string> own = data.notes();
    notes->insert(notes->end(), own.begin(), own.end());
  }
  ParticleSystem sys = data.take();
  sys.source = name;  // later refusals (engines, work estimates) name the atom's line too
  sys.source_line = data.atom_lines();
  sys.velocity_line = data.velocity_lines();
  validate_and_wrap(sys, name, &sys.source_line, rounding_eps, check_pairs);
  return sys;
}

ParticleSystem read_data(const std::string& path, std::array<bool, 3> periodic, double rounding_eps,
                         std::vector<std::string>* notes, bool check_pairs) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    throw InputError("data file '" + path + "' is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open data file '" + path + "': " + std::strerror(errno));
  return read_data(in, path, periodic, rounding_eps, notes, check_pairs);
}

}  // namespace hardsphere
