#include "hardsphere/lammps_io.hpp"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <vector>

#include "hardsphere/errors.hpp"

namespace hardsphere {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> words;
  std::istringstream s(line);
  std::string w;
  while (s >> w) words.push_back(w);
  return words;
}

std::string strip_comment(const std::string& line) {
  const auto hash = line.find('#');
  return hash == std::string::npos ? line : line.substr(0, hash);
}

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw InputError("cannot open data file '" + path + "': " + std::strerror(errno));
  }
  bool next(std::string& line) {
    if (!std::getline(in_, line)) return false;
    ++line_no_;
    return true;
  }
  // Next line that is not blank (comments removed); false at end of file.
  bool next_content(std::vector<std::string>& words, std::string* raw = nullptr) {
    std::string line;
    while (next(line)) {
      words = split(strip_comment(line));
      if (raw) *raw = line;
      if (!words.empty()) return true;
    }
    return false;
  }
  [[noreturn]] void fail(const std::string& what) const { throw FormatError(path_, line_no_, what); }
  double real(const std::string& w, const char* what) const {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(w.c_str(), &end);
    if (end == w.c_str() || *end != '\0' || errno == ERANGE) fail(std::string(what) + " '" + w + "' is not a number");
    if (!std::isfinite(v)) fail(std::string(what) + " '" + w + "' is not finite");
    return v;
  }
  std::int64_t integer(const std::string& w, const char* what) const {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(w.c_str(), &end, 10);
    if (end == w.c_str() || *end != '\0' || errno == ERANGE) fail(std::string(what) + " '" + w + "' is not an integer");
    return v;
  }
  long line() const { return line_no_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ifstream in_;
  long line_no_ = 0;
};

bool is_section(const std::vector<std::string>& w) {
  static const char* names[] = {"Atoms", "Velocities", "Masses", "Bonds", "Angles", "Dihedrals", "Impropers",
                                "Ellipsoids", "Lines", "Triangles", "Bodies", "Pair", "PairIJ", "Bond", "Angle"};
  for (const char* n : names)
    if (w[0] == n) return true;
  return false;
}

}  // namespace

ParticleSystem read_data(const std::string& path, std::array<bool, 3> periodic) {
  Reader r(path);
  std::string line;
  if (!r.next(line)) r.fail("empty file (a LAMMPS data file starts with a title line)");
  ParticleSystem sys;
  sys.box.periodic = periodic;
  std::int64_t natoms = -1, ntypes = -1;
  bool have_box[3] = {false, false, false};
  std::vector<std::string> w;
  std::string raw;
  bool have_section = r.next_content(w, &raw);
  // Header: "N atoms", "N atom types", "lo hi xlo xhi", ...
  while (have_section && !is_section(w)) {
    if (w.size() == 2 && w[1] == "atoms") natoms = r.integer(w[0], "atom count");
    else if (w.size() == 3 && w[1] == "atom" && w[2] == "types") ntypes = r.integer(w[0], "atom type count");
    else if (w.size() == 4 && (w[2] == "xlo" || w[2] == "ylo" || w[2] == "zlo")) {
      const int d = w[2][0] - 'x';
      if (w[3] != std::string(1, w[2][0]) + "hi") r.fail("expected '" + std::string(1, w[2][0]) + "hi' after '" + w[2] + "'");
      sys.box.lo[d] = r.real(w[0], "box lower bound");
      sys.box.hi[d] = r.real(w[1], "box upper bound");
      if (!(sys.box.hi[d] > sys.box.lo[d])) r.fail("box " + w[2] + " " + w[3] + " is empty: " + w[0] + " >= " + w[1]);
      have_box[d] = true;
    } else if (w.size() == 6 && w[3] == "xy") {
      r.fail("triclinic boxes (xy xz yz) are not supported");
    } else if (w.size() >= 2 && (w[1] == "bonds" || w[1] == "angles" || w[1] == "dihedrals" || w[1] == "impropers")) {
      if (r.integer(w[0], "count") != 0) r.fail("molecular topology (" + w[1] + ") is not supported for hard spheres");
    } else if (w.size() >= 3 && w[2] == "types") {
      // bond/angle/... types: harmless
    } else {
      std::string all;
      for (const auto& x : w) all += (all.empty() ? "" : " ") + x;
      r.fail("unknown header line '" + all + "'");
    }
    have_section = r.next_content(w, &raw);
  }
  if (natoms < 0) r.fail("header has no 'N atoms' line");
  if (ntypes < 1) r.fail("header has no 'N atom types' line (>= 1)");
  for (int d = 0; d < 3; ++d)
    if (!have_box[d]) r.fail(std::string("header has no '") + char('x' + d) + "lo " + char('x' + d) + "hi' line");

  std::map<std::int64_t, std::size_t> index;
  std::vector<long> atom_line;
  bool have_atoms = false;
  while (have_section) {
    const std::string name = w[0];
    if (name == "Atoms") {
      if (have_atoms) r.fail("second Atoms section");
      have_atoms = true;
      // The optional style hint ("Atoms # sphere") must say sphere if present.
      const auto hash = raw.find('#');
      if (hash != std::string::npos) {
        const auto hint = split(raw.substr(hash + 1));
        if (!hint.empty() && hint[0] != "sphere") r.fail("Atoms section is for atom_style '" + hint[0] + "'; hardsphere reads atom_style sphere");
      }
      sys.reserve(std::size_t(natoms));
      for (std::int64_t k = 0; k < natoms; ++k) {
        if (!r.next_content(w)) r.fail("Atoms section ends after " + std::to_string(k) + " of " + std::to_string(natoms) + " atoms");
        if (w.size() != 7 && w.size() != 10)
          r.fail("atom line has " + std::to_string(w.size()) + " columns; atom_style sphere needs 7 (id type diameter density x y z) or 10 (with image flags)");
        const std::int64_t id = r.integer(w[0], "atom id");
        const std::int64_t type = r.integer(w[1], "atom type");
        if (type < 1 || type > ntypes) r.fail("atom type " + w[1] + " is outside 1.." + std::to_string(ntypes));
        const double diameter = r.real(w[2], "diameter");
        const double density = r.real(w[3], "density");
        if (!(diameter > 0)) r.fail("diameter " + w[2] + " of atom " + w[0] + " must be positive (hard spheres have size)");
        if (!(density > 0)) r.fail("density " + w[3] + " of atom " + w[0] + " must be positive");
        const Vec3d p{r.real(w[4], "x"), r.real(w[5], "y"), r.real(w[6], "z")};
        if (index.count(id)) r.fail("atom id " + w[0] + " appears twice");
        const double radius = 0.5 * diameter;
        // Same operation order as LAMMPS AtomVecSphere, so masses agree to the last bit.
        const double mass = density * (4.0 * M_PI / 3.0 * radius * radius * radius);
        index[id] = sys.size();
        atom_line.push_back(r.line());
        sys.push_back(id, int(type), radius, mass, p, {});
      }
    } else if (name == "Velocities") {
      if (!have_atoms) r.fail("Velocities section before Atoms section");
      for (std::int64_t k = 0; k < natoms; ++k) {
        if (!r.next_content(w)) r.fail("Velocities section ends after " + std::to_string(k) + " of " + std::to_string(natoms) + " atoms");
        if (w.size() != 4 && w.size() != 7) r.fail("velocity line has " + std::to_string(w.size()) + " columns; expected id vx vy vz [wx wy wz]");
        const std::int64_t id = r.integer(w[0], "atom id");
        const auto it = index.find(id);
        if (it == index.end()) r.fail("velocity for unknown atom id " + w[0]);
        sys.vel[it->second] = {r.real(w[1], "vx"), r.real(w[2], "vy"), r.real(w[3], "vz")};
      }
    } else if (name == "Masses") {
      // Per-type masses are ignored by atom_style sphere (per-atom density sets the mass).
      for (std::int64_t k = 0; k < ntypes; ++k)
        if (!r.next_content(w)) r.fail("Masses section ends early");
    } else {
      r.fail("section '" + name + "' is not supported (atom_style sphere needs Atoms and optional Velocities)");
    }
    have_section = r.next_content(w, &raw);
    if (have_section && !is_section(w)) r.fail("expected a section name, found '" + w[0] + "' (more lines than the header's atom count?)");
  }
  if (!have_atoms) r.fail("no Atoms section");
  validate_and_wrap(sys, path);
  return sys;
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  tmp_ = path_ + ".tmp." + std::to_string(::getpid());
  out_.open(tmp_);
  if (!out_) throw InputError("cannot write '" + path_ + "': " + std::strerror(errno));
  out_.precision(17);
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::remove(tmp_.c_str());
  }
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw InputError("error while writing '" + path_ + "'");
  out_.close();
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw InputError("cannot move output into place at '" + path_ + "': " + std::strerror(errno));
  committed_ = true;
}

void write_data(const std::string& path, const ParticleSystem& sys, const std::string& title) {
  AtomicFile f(path);
  auto& o = f.stream();
  int ntypes = 1;
  for (int t : sys.type) ntypes = std::max(ntypes, t);
  o << title << "\n\n" << sys.size() << " atoms\n" << ntypes << " atom types\n\n";
  const char* ax[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) o << sys.box.lo[d] << ' ' << sys.box.hi[d] << ' ' << ax[d] << "lo " << ax[d] << "hi\n";
  o << "\nAtoms # sphere\n\n";
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const double r = sys.radius[i];
    const double density = sys.mass[i] / (4.0 * M_PI / 3.0 * r * r * r);
    o << sys.id[i] << ' ' << sys.type[i] << ' ' << 2 * r << ' ' << density << ' ' << sys.pos[i].x << ' '
      << sys.pos[i].y << ' ' << sys.pos[i].z << " 0 0 0\n";
  }
  o << "\nVelocities\n\n";
  for (std::size_t i = 0; i < sys.size(); ++i)
    o << sys.id[i] << ' ' << sys.vel[i].x << ' ' << sys.vel[i].y << ' ' << sys.vel[i].z << " 0 0 0\n";
  f.commit();
}

void DumpWriter::write_frame(std::int64_t timestep, const ParticleSystem& sys) {
  auto& o = file_.stream();
  o << "ITEM: TIMESTEP\n" << timestep << "\nITEM: NUMBER OF ATOMS\n" << sys.size() << "\nITEM: BOX BOUNDS";
  for (int d = 0; d < 3; ++d) o << (sys.box.periodic[d] ? " pp" : " ff");
  o << '\n';
  for (int d = 0; d < 3; ++d) o << sys.box.lo[d] << ' ' << sys.box.hi[d] << '\n';
  o << "ITEM: ATOMS id type radius x y z vx vy vz\n";
  for (std::size_t i = 0; i < sys.size(); ++i)
    o << sys.id[i] << ' ' << sys.type[i] << ' ' << sys.radius[i] << ' ' << sys.pos[i].x << ' ' << sys.pos[i].y << ' '
      << sys.pos[i].z << ' ' << sys.vel[i].x << ' ' << sys.vel[i].y << ' ' << sys.vel[i].z << '\n';
}

}  // namespace hardsphere
