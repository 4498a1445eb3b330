#include "serial_path.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "hardsphere/errors.hpp"
#include "hardsphere/state_exchange.hpp"
#include "lammps_atoms.h"
#include "output.h"
#include "update.h"

using namespace LAMMPS_NS;

namespace {

// LAMMPS's image flags: three signed counts packed into one integer (IMGBITS each).
std::array<int, 3> unpack_image(imageint img) {
  return {int(img & IMGMASK) - IMGMAX, int((img >> IMGBITS) & IMGMASK) - IMGMAX, int(img >> IMG2BITS) - IMGMAX};
}

imageint pack_image(const std::array<int, 3> &f) {
  return (imageint(f[0] + IMGMAX) & IMGMASK) | ((imageint(f[1] + IMGMAX) & IMGMASK) << IMGBITS) |
         ((imageint(f[2] + IMGMAX) & IMGMASK) << IMG2BITS);
}

}  // namespace

void SerialPath::make(const std::string &source, const std::string &hint) {
  // A fresh stepper at every run: velocity, displace_atoms, set or read_restart may have
  // changed anything between runs.
  AtomRows rows;
  rows.rough = physics_.rough();  // the fix checked that the atom style has omega
  hardsphere::ParticleSystem sys = atoms_to_system(atom, lammps_box(domain), rows);
  try {
    // Overlaps, out-of-box atoms; overlaps the stepper's own rounding leaves (a state it
    // ended a run with) are accepted, as the standalone's --read-data accepts them.
    hardsphere::validate_and_wrap(sys, source, nullptr, hardsphere::rounding_epsilon(hardsphere::Precision::Double));
    stepper_ = hardsphere::make_stepper(sys, physics_, config_);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string(e.what()) + "; " + hint);
  }
  // Both copies hold the same trajectory: LAMMPS's unwrapped position (x + image L) is the
  // stepper's (position + its wrap count L) plus a whole number of box lengths per axis,
  // fixed now and kept by tag so LAMMPS may re-order its atoms.
  map_tags();
  tag_image0_.assign(tag_local_.size(), {0, 0, 0});
  input_tag_.assign(sys.id.begin(), sys.id.end());
  for (std::size_t k = 0; k < sys.size(); k++) {
    const int i = tag_local_[std::size_t(sys.id[k])];
    const std::array<int, 3> flags = unpack_image(atom->image[i]);
    for (int d = 0; d < 3; d++)
      tag_image0_[std::size_t(sys.id[k])][std::size_t(d)] =
          flags[std::size_t(d)] +
          (domain->periodicity[d] ? int(std::nearbyint((atom->x[i][d] - sys.pos[k][d]) / domain->prd[d])) : 0);
  }
  slots_dirty_ = true;
  lammps_moved_ = false;
  // Other fixes' setup may still change velocities: compare at the first step.
  keep_written();
  state_written_ = true;
}

void SerialPath::map_tags() {
  // Atomic styles keep no tag -> index map by default (atom_modify map): make one.
  const int nlocal = atom->nlocal;
  mapped_tags_.assign(atom->tag, atom->tag + nlocal);
  const tagint max_tag = nlocal ? *std::max_element(mapped_tags_.begin(), mapped_tags_.end()) : 0;
  tag_local_.assign(std::size_t(max_tag) + 1, -1);
  for (int i = 0; i < nlocal; i++) tag_local_[std::size_t(atom->tag[i])] = i;
}

void SerialPath::map_if_stale() {
  if (slots_dirty_ || slots_.stale(*stepper_)) map();
}

void SerialPath::map() {
  // LAMMPS's x = stepper position + (stepper wraps + the atom's fixed offset - LAMMPS's image
  // flags) L, so that x moves continuously and LAMMPS wraps it itself when it re-neighbours.
  // Only an atom that has travelled far while nothing was written (sparse writes) is re-imaged
  // here, so that x stays within half a box of the box.
  auto &exch = hardsphere::state_exchange(*stepper_);
  const std::size_t n = exch.size();
  imageint *image = atom->image;
  input_row_.resize(n), input_offset_.resize(n);
  for (std::size_t in = 0; in < n; in++) {
    const std::size_t tag = std::size_t(input_tag_[in]);
    const int i = tag < tag_local_.size() ? tag_local_[tag] : -1;
    if (i < 0) error->one(FLERR, "fix hardsphere: atom " + std::to_string(tag) + " is no longer on this rank");
    input_row_[in] = i;
    const std::array<int, 3> flags = unpack_image(image[i]);
    for (int d = 0; d < 3; d++)
      input_offset_[in][std::size_t(d)] =
          domain->periodicity[d] ? tag_image0_[tag][std::size_t(d)] - flags[std::size_t(d)] : 0;
  }
  slots_.make(*stepper_, input_row_, {}, input_offset_, domain->prd, atom->nlocal);
  slot_pos_.resize(n), slot_vel_.resize(n);
  exch.copy(hardsphere::SphereField::Position, nullptr, slot_pos_.size(), slot_pos_.data());
  exch.copy(hardsphere::SphereField::Velocity, nullptr, slot_vel_.size(), slot_vel_.data());
  for (std::size_t k = 0; k < n; k++) {
    const int i = int(slots_.rows()[k]);
    std::array<int, 3> flags = unpack_image(image[i]);
    bool reimaged = false;
    for (int d = 0; d < 3; d++) {
      if (!domain->periodicity[d]) continue;
      const double len = domain->prd[d];
      const double x = slot_pos_[k][d] + slots_.shifts()[k][d];
      if (x < domain->boxlo[d] - 0.5 * len || x >= domain->boxhi[d] + 0.5 * len) {
        const int w = int(std::floor((x - domain->boxlo[d]) / len));
        flags[std::size_t(d)] += w;
        slots_.move(k, d, -w);
        reimaged = true;
      }
    }
    if (reimaged) image[i] = pack_image(flags);
  }
  mapped_image_.assign(image, image + n);
  slots_dirty_ = false;
}

void SerialPath::follow_lammps() {
  // If LAMMPS sorted its atoms, the tag map and slots are made anew. Otherwise it only wrapped
  // some atoms, each wrap changing an image flag: shift those.
  lammps_moved_ = false;
  const int nlocal = atom->nlocal;
  if (std::size_t(nlocal) != hardsphere::state_exchange(*stepper_).size())
    error->all(FLERR, "fix hardsphere: atoms were added or removed during a run (" + std::to_string(nlocal) + " now, " +
                          std::to_string(hardsphere::state_exchange(*stepper_).size()) + " at its start)");
  if (!std::equal(atom->tag, atom->tag + nlocal, mapped_tags_.begin())) {
    map_tags();
    slots_dirty_ = true;
  }
  if (slots_dirty_) return;
  const imageint *image = atom->image;
  for (int i = 0; i < nlocal; i++) {
    if (image[i] == mapped_image_[std::size_t(i)]) continue;
    const std::array<int, 3> now = unpack_image(image[i]), before = unpack_image(mapped_image_[std::size_t(i)]);
    for (int d = 0; d < 3; d++)  // x + L comes with image - 1
      if (now[std::size_t(d)] != before[std::size_t(d)])
        slots_.move(slots_.slot_of_row(i), d, before[std::size_t(d)] - now[std::size_t(d)]);
    mapped_image_[std::size_t(i)] = image[i];
  }
}

void SerialPath::write() {
  map_if_stale();
  auto &exch = hardsphere::state_exchange(*stepper_);
  if (slots_.size()) exch.scatter_state(slots_.rows(), slots_.shifts(), atom->x[0], atom->v[0]);
  // Rough spheres: compute erotate/sphere, temp/sphere and dumps read LAMMPS's omega.
  if (slots_.size() && physics_.rough()) exch.scatter(hardsphere::SphereField::Omega, slots_.rows(), atom->omega[0]);
  state_written_ = true;
}

void SerialPath::keep_written() {
  const int nlocal = atom->nlocal;
  const bool keep = others_.any() && nlocal > 0;
  if (keep)
    v_written_.assign(atom->v[0], atom->v[0] + 3 * nlocal);
  else
    v_written_.clear();
  if (keep && physics_.rough())
    w_written_.assign(atom->omega[0], atom->omega[0] + 3 * nlocal);
  else
    w_written_.clear();
}

bool SerialPath::must_write() const {
  const bigint t = update->ntimestep;
  return t == output->next || t >= update->laststep || others_.acted(t) || others_.reads(t) || others_.changes_atoms(t);
}

bool SerialPath::before_step(const StepStart &start) {
  bool fresh = false;
  if (start.without_setup) {  // commands between runs may have changed atoms
    make("fix hardsphere", kStartHint);
    fresh = true;
  }
  timer_.start();
  if (!start.moved_by.empty()) {  // made again from LAMMPS's atoms, checked as at a run's start
    make(start.moved_by, kMovedAtomsHint);
    v_written_.clear();
    w_written_.clear();
    fresh = true;
  }
  if (!atoms_changed_by_.empty()) {  // a new set of atoms: made again from LAMMPS's rows
    make(atoms_changed_by_, kInsertedAtomsHint);
    atoms_changed_by_.clear();
    v_written_.clear();
    w_written_.clear();
    fresh = true;
  }
  if (lammps_moved_) follow_lammps();
  // LAMMPS's copy of x and v is written only when something will look at it: on output steps
  // (thermo, dump, restart), at the run's last step, when the run ends, whenever another fix
  // acts (every step for fixes hooked into the step, every nevery for end_of_step ones) and on a
  // dynamic group's steps.
  // After such a write a fix may have changed velocities (a thermostat): take them up.
  const int nlocal = atom->nlocal;
  if (!v_written_.empty()) {
    const double *v = atom->v[0];
    if (v_written_.size() != std::size_t(3 * nlocal) || !std::equal(v, v + 3 * nlocal, v_written_.begin())) {
      map_if_stale();
      hardsphere::state_exchange(*stepper_).gather(hardsphere::SphereField::Velocity, slots_.rows(), v);
      fresh = true;
    }
    v_written_.clear();
  }
  if (!w_written_.empty()) {  // the same for angular velocities (rough spheres)
    const double *w = atom->omega[0];
    if (w_written_.size() != std::size_t(3 * nlocal) || !std::equal(w, w + 3 * nlocal, w_written_.begin())) {
      map_if_stale();
      hardsphere::state_exchange(*stepper_).gather(hardsphere::SphereField::Omega, slots_.rows(), w);
    }
    w_written_.clear();
  }
  timer_.charge(PartTimer::Follow);
  return fresh;
}

StepTotals SerialPath::step(double *virial_rows, double scale) {
  const int nlocal = atom->nlocal;
  auto &exch = hardsphere::state_exchange(*stepper_);
  const hardsphere::StepCounters before = stepper_->counters();
  exch.set_sphere_virial(virial_rows != nullptr);
  try {
    stepper_->run(1);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: ") + e.what());
  }
  timer_.charge(PartTimer::Steps);
  if (virial_rows) {  // this step's share per atom, into the rows LAMMPS keeps with the atoms
    map_if_stale();
    std::fill(virial_rows, virial_rows + 6 * nlocal, 0.0);
    exch.take_sphere_virial(slots_.rows(), scale, virial_rows);
  }
  const hardsphere::StepCounters &after = stepper_->counters();
  state_written_ = false;
  const bigint now = update->ntimestep;
  if (others_.changes_atoms(now))  // in this step's pre_exchange, after the write below
    atoms_changed_by_ = "fix hardsphere: after " + others_.atom_changers(now) + " at step " + std::to_string(now);
  if (must_write()) {
    write();
    keep_written();
  }
  timer_.charge(PartTimer::Write);

  StepTotals t;
  static_cast<hardsphere::WeightedCollisionTotals &>(t) =
      hardsphere::collision_totals<double>(after) - hardsphere::collision_totals<double>(before);
  t.unresolved = double(after.unresolved_steps - before.unresolved_steps);
  return t;
}
