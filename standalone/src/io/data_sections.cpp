// LAMMPS's other data-file sections for atom_style sphere: what write_data writes with a pair
// style (Pair Coeffs, PairIJ Coeffs), with bond styles of a hybrid set-up (zero bonds, their
// coefficients) and with type labels. hardsphere's own contact distances are checked as fix
// hardsphere checks them; everything else describes a model hard spheres do not have and is
// skipped with a note, so a LAMMPS file round-trips through the command line.
#include "io/data_sections.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "hardsphere/format.hpp"

namespace hardsphere::data {

namespace {

//! A type-indexed section: its kind ("Pair", "Bond Type Labels" -> "Bond") and what it holds.
struct Kind {
  const char* name;
  const char* unit;  // what the header counts: "atom types", ...
  std::int64_t TypeCounts::*count;
};

const Kind kCoeffKinds[] = {
    {"Pair", "atom types", &TypeCounts::atom},
    {"PairIJ", "atom types", &TypeCounts::atom},
    {"Bond", "bond types", &TypeCounts::bond},
    {"Angle", "angle types", &TypeCounts::angle},
    {"Dihedral", "dihedral types", &TypeCounts::dihedral},
    {"Improper", "improper types", &TypeCounts::improper},
    {"BondBond", "angle types", &TypeCounts::angle},
    {"BondAngle", "angle types", &TypeCounts::angle},
    {"MiddleBondTorsion", "dihedral types", &TypeCounts::dihedral},
    {"EndBondTorsion", "dihedral types", &TypeCounts::dihedral},
    {"AngleTorsion", "dihedral types", &TypeCounts::dihedral},
    {"AngleAngleTorsion", "dihedral types", &TypeCounts::dihedral},
    {"BondBond13", "dihedral types", &TypeCounts::dihedral},
    {"AngleAngle", "improper types", &TypeCounts::improper},
};

const Kind kLabelKinds[] = {
    {"Atom", "atom types", &TypeCounts::atom},
    {"Bond", "bond types", &TypeCounts::bond},
    {"Angle", "angle types", &TypeCounts::angle},
    {"Dihedral", "dihedral types", &TypeCounts::dihedral},
    {"Improper", "improper types", &TypeCounts::improper},
};

const Kind* find_kind(const std::string& title) {
  for (const Kind& k : kCoeffKinds)
    if (title == std::string(k.name) + " Coeffs") return &k;
  for (const Kind& k : kLabelKinds)
    if (title == std::string(k.name) + " Type Labels") return &k;
  return nullptr;
}

//! The style a section line names in its comment ("Pair Coeffs # hardsphere"), or "".
std::string style_hint(const std::string& raw) {
  const auto hash = raw.find('#');
  if (hash == std::string::npos) return "";
  const Words w = split(raw.substr(hash + 1));
  return w.empty() ? "" : w[0];
}

std::string where(const LineReader& r, long line) { return r.name() + ":" + std::to_string(line) + ": "; }

}  // namespace

std::string ExtraSections::title(const Words& w) {
  if (is_section_line(w)) {
    std::string t = w[0];
    for (std::size_t k = 1; k < w.size(); ++k) t += " " + w[k];
    return t;
  }
  return join(w);
}

bool ExtraSections::handles(const std::string& title) { return find_kind(title) != nullptr; }

void ExtraSections::read(LineReader& r, const std::string& title, const std::string& raw, const TypeCounts& counts) {
  const Kind& kind = *find_kind(title);
  const long first = r.line();
  const std::int64_t types = counts.*kind.count;
  if (types < 1) r.fail(title + " section, but the header has no " + kind.unit);
  const bool pair_ij = std::string(kind.name) == "PairIJ", labels = title.find("Labels") != std::string::npos;
  const std::int64_t rows = pair_ij ? types * (types + 1) / 2 : types;
  const std::string style = style_hint(raw);
  const bool ours = (std::string(kind.name) == "Pair" || pair_ij) && style == "hardsphere";
  const std::string range = "1.." + std::to_string(types) + ", the header's " + kind.unit;
  std::map<std::pair<std::int64_t, std::int64_t>, long> seen;  // the type (pair) of each row, once
  std::set<std::string> names;
  Words w;
  for (std::int64_t k = 0; k < rows; ++k) {
    next_row(r, w, title.c_str(), k, rows, "rows");
    const std::size_t indices = pair_ij ? 2 : 1;
    if (w.size() < indices) r.fail(title + " row needs " + (pair_ij ? "two types" : "a type"));
    std::int64_t a = r.integer(w[0], "type", 1, types, range), b = 0;
    if (pair_ij) {
      b = r.integer(w[1], "type", 1, types, range);
      if (b < a) std::swap(a, b);
    }
    const auto [it, fresh] = seen.emplace(std::make_pair(a, b), r.line());
    if (!fresh)
      r.fail(title + " row for type " + (pair_ij ? std::to_string(a) + " " + std::to_string(b) : std::to_string(a)) +
             " given twice (first at line " + std::to_string(it->second) + ")");
    if (labels) {
      if (w.size() != 2) r.fail(title + " row has " + std::to_string(w.size()) + " words; expected 'type label'");
      if (!names.insert(w[1]).second) r.fail("type label '" + shown(w[1]) + "' given twice");
    } else if (ours) {
      if (w.size() != indices + 1)
        r.fail("pair_style hardsphere's " + title + " row has " + std::to_string(w.size()) + " words; expected '" +
               (pair_ij ? "I J" : "I") + " contact-distance'");
      const double d = r.real(w[indices], "contact distance");
      if (!(d > 0)) r.fail("contact distance " + shown(w[indices]) + " must be positive");
      contacts_.push_back({a, b, d, r.line()});
    }
  }
  if (ours) return;
  std::string why;
  if (labels)
    why = "hardsphere numbers the types, and the files it writes carry the numbers only";
  else if (std::string(kind.name) == "Pair" || pair_ij)
    why = std::string("they are ") + (style.empty() ? "another pair style's" : "pair_style " + style + "'s") +
          "; hard spheres collide at the sum of their radii and feel no force";
  else
    why = "there are no bonds, angles, dihedrals or impropers between hard spheres";
  notes_.push_back(where(r, first) + title + (style.empty() ? "" : " # " + style) + " skipped: " + why);
}

void ExtraSections::check(const ParticleSystem& sys, const std::vector<long>& atom_lines,
                          const std::string& file) const {
  if (contacts_.empty()) return;
  // The largest radius of each type and the atom that has it.
  std::map<std::int64_t, std::size_t> widest;
  for (std::size_t i = 0; i < sys.size(); ++i) {
    const auto it = widest.find(sys.type[i]);
    if (it == widest.end() || sys.radius[i] > sys.radius[it->second]) widest[sys.type[i]] = i;
  }
  std::map<std::int64_t, const Contact*> own;  // Pair Coeffs rows by type
  for (const Contact& c : contacts_)
    if (c.j == 0) own[c.i] = &c;
  auto check_pair = [&](std::int64_t a, std::int64_t b, double contact, long line) {
    const auto ia = widest.find(a), ib = widest.find(b);
    if (ia == widest.end() || ib == widest.end()) return;
    const std::size_t i = ia->second, j = ib->second;
    const double reach = sys.radius[i] + sys.radius[j];
    if (reach > contact * (1 + 1e-12)) {
      std::ostringstream m;
      m << "contact distance " << format_number(contact) << " of atom types " << a << " and " << b << " is below ";
      if (i == j)
        m << "the diameter " << format_number(reach) << " of atom " << sys.id[i] << " (line " << atom_lines[i] << ")";
      else
        m << "the contact distance " << format_number(reach) << " of atoms " << sys.id[i] << " (line " << atom_lines[i]
          << ") and " << sys.id[j] << " (line " << atom_lines[j] << ")";
      m << ": fix hardsphere refuses it; raise it or leave out the section (hardsphere takes contacts from the "
           "radii)";
      throw FormatError(file, line, m.str());
    }
  };
  for (const Contact& c : contacts_) {
    if (c.j != 0) {  // PairIJ: the pair's own distance
      check_pair(c.i, c.j, c.distance, c.line);
      continue;
    }
    check_pair(c.i, c.i, c.distance, c.line);
    for (const auto& [b, other] : own)  // LAMMPS mixes the others geometrically (its default)
      if (b > c.i) check_pair(c.i, b, std::sqrt(c.distance * other->distance), std::max(c.line, other->line));
  }
}

}  // namespace hardsphere::data
