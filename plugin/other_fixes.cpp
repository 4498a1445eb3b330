#include "other_fixes.h"

#include <algorithm>
#include <string>

#include "fix.h"
#include "modify.h"
#include "utils.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

// Fixes that may act between steps (end_of_step) and are known to leave positions alone:
// thermostats and velocity exchanges, averages, output and bookkeeping. Any other (python/invoke,
// say) may move atoms, so the fix compares LAMMPS's x after it acts.
bool keeps_positions(const Fix *f) {
  for (const char *prefix : {"^ave/", "^temp/", "^store/"})
    if (utils::strmatch(f->style, prefix)) return true;
  for (const char *style : {"heat", "momentum", "momentum/chunk", "print", "halt", "vector", "balance", "setforce",
                            "gravity", "thermal/conductivity", "viscosity", "heat/flow", "add/heat"})
    if (std::string(f->style) == style) return true;
  return false;
}

}  // namespace

void OtherFixes::scan(const Modify *modify, const Fix *self) {
  every_step_ = false;
  every_.clear();
  readers_.clear();
  movers_.clear();
  changers_.clear();
  inserts_ = false;
  const int per_step = INITIAL_INTEGRATE | POST_INTEGRATE | PRE_EXCHANGE | PRE_NEIGHBOR | POST_NEIGHBOR | PRE_FORCE |
                       PRE_REVERSE | POST_FORCE | FINAL_INTEGRATE;
  for (int f = 0; f < modify->nfix; f++) {
    const Fix *fix = modify->fix[f];
    if (fix == self) continue;
    // fix gravity only adds forces (its acceleration acts through the stepper) and reads x for
    // its energy, which output steps write anyway.
    if (utils::strmatch(fix->style, "^gravity")) continue;
    // fix freeze only zeroes forces: its atoms are the stepper's kinematic spheres.
    if (std::string(fix->style) == "freeze") continue;
    // Insertions and deletions happen on the steps the fix schedules, not every step: the paths
    // write LAMMPS's rows before them and read the new set of atoms after.
    if (is_atom_changer(fix)) {
      changers_.push_back(fix);
      inserts_ |= std::string(fix->style) != "evaporate";
      continue;
    }
    // A dynamic group sets its members from x (region, variable, 'within') every nevery steps,
    // called outside the fix lists since LAMMPS 2025 (mask 0): it reads, never changes, atoms.
    if (std::string(fix->style) == "GROUP") {
      readers_.push_back(std::max(1, fix->nevery));
      continue;
    }
    if (modify->fmask[f] & per_step)
      every_step_ = true;
    else if (modify->fmask[f] & END_OF_STEP)
      every_.push_back(std::max(1, fix->nevery));
    else
      continue;
    if (!keeps_positions(fix))
      movers_ += (movers_.empty() ? "fix " : ", fix ") + std::string(fix->id) + " (" + fix->style + ")";
  }
}

bool OtherFixes::acted(bigint step) const {
  if (every_step_) return true;
  for (const int every : every_)
    if (step % every == 0) return true;
  return false;
}

bool OtherFixes::is_atom_changer(const Fix *f) {
  for (const char *style : {"pour", "deposit", "evaporate"})
    if (std::string(f->style) == style) return true;
  return false;
}

double OtherFixes::inserted_radius(const Modify *modify, int type) {
  double largest = 0.0;
  for (int i = 0; i < modify->nfix; i++) {
    if (!is_atom_changer(modify->fix[i])) continue;
    int t = type;  // extract() may change it
    if (auto *r = static_cast<double *>(modify->fix[i]->extract("radius", t))) largest = std::max(largest, *r);
  }
  return largest;
}

bool OtherFixes::changes_atoms(bigint step) const {
  for (const Fix *f : changers_)
    if (f->force_reneighbor && f->next_reneighbor == step) return true;
  return false;
}

std::string OtherFixes::atom_changers(bigint step) const {
  std::string out;
  for (const Fix *f : changers_)
    if (f->force_reneighbor && f->next_reneighbor == step)
      out += (out.empty() ? "fix " : ", fix ") + std::string(f->id) + " (" + f->style + ")";
  return out;
}

bool OtherFixes::reads(bigint step) const {
  for (const int every : readers_)
    if (step % every == 0) return true;
  return false;
}
