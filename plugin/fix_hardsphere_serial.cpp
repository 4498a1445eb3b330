// fix hardsphere on one rank: the owned atoms are handed to the standalone stepper, which
// resolves periodic images itself, so LAMMPS builds no neighbour list for the fix and every
// result is the standalone stepper's by construction. LAMMPS keeps its own copy of x and v
// (for output, other fixes, restarts): after each step the stepper's state is written back
// through a slot -> local-atom map that is rebuilt only when either side re-orders its atoms.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "fix_hardsphere.h"
#include "force.h"
#include "hardsphere/errors.hpp"
#include "hardsphere/particles.hpp"
#include "hardsphere/state_exchange.hpp"
#include "modify.h"
#include "output.h"
#include "update.h"
#include "utils.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

// LAMMPS's image flags: three signed counts packed into one integer (IMGBITS each).
std::array<int, 3> unpack_image(imageint img) {
  return {int(img & IMGMASK) - IMGMAX, int((img >> IMGBITS) & IMGMASK) - IMGMAX, int(img >> IMG2BITS) - IMGMAX};
}

imageint pack_image(const std::array<int, 3> &f) {
  return (imageint(f[0] + IMGMAX) & IMGMASK) | ((imageint(f[1] + IMGMAX) & IMGMASK) << IMGBITS) |
         ((imageint(f[2] + IMGMAX) & IMGMASK) << IMG2BITS);
}

// Fixes that may act between steps (end_of_step) and are known to leave positions alone:
// thermostats and velocity exchanges, averages, output and bookkeeping. Any other (python/invoke,
// say) may move atoms, so the fix compares LAMMPS's x after it acts.
bool keeps_positions(const Fix *f) {
  for (const char *prefix : {"^ave/", "^temp/", "^store/"})
    if (utils::strmatch(f->style, prefix)) return true;
  for (const char *style : {"heat", "momentum", "momentum/chunk", "print", "halt", "vector", "balance", "setforce",
                            "gravity", "thermal/conductivity", "viscosity"})
    if (std::string(f->style) == style) return true;
  return false;
}

}  // namespace

void FixHardSphere::serial_setup(const std::string &source, const std::string &hint) {
  // A fresh stepper at every run: velocity, displace_atoms, set or read_restart may have
  // changed anything between runs.
  const int nlocal = atom->nlocal;
  hardsphere::ParticleSystem sys = empty_system();
  sys.reserve(std::size_t(nlocal));
  for (int i = 0; i < nlocal; i++)
    sys.push_back(std::int64_t(atom->tag[i]), atom->type[i], atom->radius[i], atom->rmass[i],
                  {atom->x[i][0], atom->x[i][1], atom->x[i][2]}, {atom->v[i][0], atom->v[i][1], atom->v[i][2]});
  try {
    hardsphere::validate_and_wrap(sys, source);  // overlaps, out-of-box atoms
    stepper = new_stepper(sys);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string(e.what()) + "; " + hint);
  }
  // Both copies hold the same trajectory: LAMMPS's unwrapped position (x + image L) is the
  // stepper's (position + its wrap count L) plus a whole number of box lengths per axis,
  // fixed now and kept by tag so LAMMPS may re-order its atoms.
  map_tags();
  tag_image0.assign(tag_local.size(), {0, 0, 0});
  for (std::size_t k = 0; k < sys.size(); k++) {
    const int i = tag_local[std::size_t(sys.id[k])];
    const std::array<int, 3> flags = unpack_image(atom->image[i]);
    for (int d = 0; d < 3; d++)
      tag_image0[std::size_t(sys.id[k])][std::size_t(d)] =
          flags[std::size_t(d)] +
          (domain->periodicity[d] ? int(std::nearbyint((atom->x[i][d] - sys.pos[k][d]) / domain->prd[d])) : 0);
  }
  slots_dirty = true;
  lammps_moved = false;
  // Other fixes' setup may still change velocities: compare at the first step.
  if ((others_every_step || !others_every.empty()) && nlocal > 0)
    v_written.assign(atom->v[0], atom->v[0] + 3 * nlocal);
  else
    v_written.clear();
  state_written = true;
}

void FixHardSphere::serial_schedule() {
  // When do other fixes look at or change x and v? A fix hooked into the step's stages reads
  // them every step; one that only acts at end_of_step does so every nevery steps.
  others_every_step = false;
  others_every.clear();
  movers.clear();
  const int per_step = INITIAL_INTEGRATE | POST_INTEGRATE | PRE_EXCHANGE | PRE_NEIGHBOR | POST_NEIGHBOR | PRE_FORCE |
                       PRE_REVERSE | POST_FORCE | FINAL_INTEGRATE;
  for (int f = 0; f < modify->nfix; f++) {
    if (modify->fix[f] == this) continue;
    // fix gravity only adds forces (its acceleration acts through the stepper) and reads x for
    // its energy, which output steps write anyway.
    if (utils::strmatch(modify->fix[f]->style, "^gravity")) continue;
    if (modify->fmask[f] & per_step)
      others_every_step = true;
    else if (modify->fmask[f] & END_OF_STEP)
      others_every.push_back(std::max(1, modify->fix[f]->nevery));
    else
      continue;
    if (!keeps_positions(modify->fix[f]))
      movers +=
          (movers.empty() ? "fix " : ", fix ") + std::string(modify->fix[f]->id) + " (" + modify->fix[f]->style + ")";
  }
}

bool FixHardSphere::positions_moved() const {
  // x_kept holds the owned rows as they were before the other fixes' step-end hooks (see
  // post_force); LAMMPS neither re-orders nor wraps atoms between those hooks and this step.
  const int nlocal = atom->nlocal;
  int moved = x_kept.size() != std::size_t(3 * nlocal) ||
              (nlocal > 0 && !std::equal(atom->x[0], atom->x[0] + 3 * nlocal, x_kept.begin()));
  MPI_Allreduce(MPI_IN_PLACE, &moved, 1, MPI_INT, MPI_MAX, world);
  return moved != 0;
}

bool FixHardSphere::others_acted(bigint step) const {
  if (others_every_step) return true;
  for (const int every : others_every)
    if (step % every == 0) return true;
  return false;
}

bool FixHardSphere::serial_must_write() const {
  const bigint t = update->ntimestep;
  return t == output->next || t >= update->laststep || others_acted(t);
}

hardsphere::ParticleSystem FixHardSphere::empty_system() const {
  hardsphere::ParticleSystem sys;
  for (int d = 0; d < 3; d++) {
    sys.box.lo[d] = domain->boxlo[d], sys.box.hi[d] = domain->boxhi[d];
    sys.box.periodic[d] = domain->periodicity[d] != 0;
  }
  return sys;
}

hardsphere::StepperConfig FixHardSphere::stepper_config() const {
  hardsphere::StepperConfig cfg;
  cfg.dt = dt;
  cfg.detect = sweep ? hardsphere::Detect::Sweep : hardsphere::Detect::Overlap;
  cfg.max_events_per_step = max_events;
  return cfg;
}

std::unique_ptr<hardsphere::StepperBase> FixHardSphere::new_stepper(const hardsphere::ParticleSystem &sys) const {
  return hardsphere::make_stepper(sys, physics, stepper_config());
}

void FixHardSphere::map_tags() {
  // Atomic styles keep no tag -> index map by default (atom_modify map): make one.
  const int nlocal = atom->nlocal;
  mapped_tags.assign(atom->tag, atom->tag + nlocal);
  const tagint max_tag = nlocal ? *std::max_element(mapped_tags.begin(), mapped_tags.end()) : 0;
  tag_local.assign(std::size_t(max_tag) + 1, -1);
  for (int i = 0; i < nlocal; i++) tag_local[std::size_t(atom->tag[i])] = i;
}

void FixHardSphere::serial_map_if_stale() {
  // The slots follow the stepper's order, which changes at each of its rebuilds.
  if (slots_dirty || stepper->counters().rebuilds != slot_rebuilds) serial_map();
}

void FixHardSphere::serial_map() {
  // Which LAMMPS atom each stepper slot is, and the shift from the stepper's position to
  // LAMMPS's: the atom's unwrapped position is the same in both, so LAMMPS's x = stepper
  // position + (stepper wraps + the atom's fixed offset - LAMMPS's image flags) L. LAMMPS's
  // x then moves continuously and LAMMPS wraps it itself when it re-neighbours. Only an atom
  // that has travelled far while nothing was written (sparse writes) is re-imaged here, so
  // that x stays within half a box of the box. Needed after the stepper re-sorted its cells or
  // LAMMPS re-neighboured, and only before a write.
  const std::size_t n = hardsphere::state_exchange(*stepper).size();
  slot_id.resize(n), slot_image.resize(3 * n), slot_local.resize(n), slot_shift.resize(n);
  slot_pos.resize(n), slot_vel.resize(n), local_slot.resize(n);
  hardsphere::state_exchange(*stepper).copy_ids(slot_id.data());
  hardsphere::state_exchange(*stepper).copy_images(slot_image.data());
  hardsphere::state_exchange(*stepper).copy_state(slot_pos.data(), slot_vel.data());
  imageint *image = atom->image;
  for (std::size_t k = 0; k < n; k++) {
    const std::size_t tag = std::size_t(slot_id[k]);
    const int i = tag < tag_local.size() ? tag_local[tag] : -1;
    if (i < 0) error->one(FLERR, "fix hardsphere: atom " + std::to_string(slot_id[k]) + " is no longer on this rank");
    slot_local[k] = std::uint32_t(i);
    local_slot[std::size_t(i)] = std::uint32_t(k);
    std::array<int, 3> flags = unpack_image(image[i]);
    bool reimaged = false;
    for (int d = 0; d < 3; d++) {
      slot_shift[k][d] = 0.0;
      if (!domain->periodicity[d]) continue;
      const double len = domain->prd[d];
      int m = slot_image[3 * k + d] + tag_image0[tag][std::size_t(d)] - flags[std::size_t(d)];
      const double x = slot_pos[k][d] + m * len;
      if (x < domain->boxlo[d] - 0.5 * len || x >= domain->boxhi[d] + 0.5 * len) {
        const int w = int(std::floor((x - domain->boxlo[d]) / len));
        flags[std::size_t(d)] += w, m -= w;
        reimaged = true;
      }
      slot_shift[k][d] = m * len;
    }
    if (reimaged) image[i] = pack_image(flags);
  }
  mapped_image.assign(image, image + n);
  slot_rebuilds = stepper->counters().rebuilds;
  slots_dirty = false;
}

void FixHardSphere::serial_follow_lammps() {
  // LAMMPS re-neighboured. If it sorted its atoms, the tag map and slots are made anew.
  // Otherwise it only wrapped some atoms, each wrap changing an image flag: shift those.
  lammps_moved = false;
  const int nlocal = atom->nlocal;
  if (std::size_t(nlocal) != hardsphere::state_exchange(*stepper).size())
    error->all(FLERR, "fix hardsphere: atoms were added or removed during a run (" + std::to_string(nlocal) + " now, " +
                          std::to_string(hardsphere::state_exchange(*stepper).size()) + " at its start)");
  if (!std::equal(atom->tag, atom->tag + nlocal, mapped_tags.begin())) {
    map_tags();
    slots_dirty = true;
  }
  if (slots_dirty) return;
  const imageint *image = atom->image;
  for (int i = 0; i < nlocal; i++) {
    if (image[i] == mapped_image[std::size_t(i)]) continue;
    const std::array<int, 3> now = unpack_image(image[i]), before = unpack_image(mapped_image[std::size_t(i)]);
    for (int d = 0; d < 3; d++)  // x + L comes with image - 1
      slot_shift[local_slot[std::size_t(i)]][d] -= (now[std::size_t(d)] - before[std::size_t(d)]) * domain->prd[d];
    mapped_image[std::size_t(i)] = image[i];
  }
}

void FixHardSphere::serial_write() {
  serial_map_if_stale();
  if (!slot_local.empty())
    hardsphere::state_exchange(*stepper).scatter_state(slot_local.data(), slot_shift.data(), atom->x[0], atom->v[0]);
  state_written = true;
}

void FixHardSphere::serial_step(bool take_atom_virial, bool moved) {
  if (!run_set_up) {  // 'run ... pre no': no setup(), but commands between runs may have changed atoms
    serial_setup();
    t_now = temperature_now();
    run_set_up = true;
  }
  timing.start();
  if (moved) {  // made again from LAMMPS's atoms, checked as at a run's start, velocities included
    serial_setup(moved_source(), kMovedAtomsHint);
    t_now = temperature_now();
    v_written.clear();
  }
  if (lammps_moved) serial_follow_lammps();
  const int nlocal = atom->nlocal;
  double *v = nlocal ? atom->v[0] : nullptr;  // LAMMPS's per-atom rows are one contiguous block

  // LAMMPS's copy of x and v is written only when something will look at it: on output steps
  // (thermo, dump, restart), at the run's last step, when the run ends, and whenever another
  // fix acts (every step for fixes hooked into the step, every nevery for end_of_step ones).
  // After such a write a fix may have changed velocities (a thermostat): take them up.
  if (!v_written.empty()) {
    if (v_written.size() != std::size_t(3 * nlocal) || !std::equal(v, v + 3 * nlocal, v_written.begin())) {
      serial_map_if_stale();
      hardsphere::state_exchange(*stepper).gather_velocities(slot_local.data(), v);
      t_now = temperature_now();
    }
    v_written.clear();
  }
  timing.charge(PartTimer::Follow);

  const hardsphere::StepCounters before = stepper->counters();
  hardsphere::state_exchange(*stepper).set_sphere_virial(take_atom_virial);
  stepper->run(1);
  timing.charge(PartTimer::Steps);
  if (take_atom_virial) {  // this step's share per atom, into the rows LAMMPS keeps with the atoms
    serial_map_if_stale();
    std::fill(vstep[0], vstep[0] + 6 * nlocal, 0.0);
    hardsphere::state_exchange(*stepper).take_sphere_virial(slot_local.data(), force->mvv2e / dt, vstep[0]);
    vstep_at = update->ntimestep;
  }
  const hardsphere::StepCounters &after = stepper->counters();
  state_written = false;
  if (serial_must_write()) {
    serial_write();
    if (others_every_step || !others_every.empty()) v_written.assign(v, v + 3 * nlocal);
  }
  timing.charge(PartTimer::Write);

  n_coll_step = double(after.collisions - before.collisions);
  n_coll += n_coll_step;
  for (int k = 0; k < 6; k++) step_virial[k] = after.pair_virial_tensor[k] - before.pair_virial_tensor[k];
  virial_sum += after.pair_virial - before.pair_virial;
  n_wall += double(after.wall_collisions - before.wall_collisions);
  n_unresolved += double(after.unresolved_steps - before.unresolved_steps);
  sim_time += dt;
  if (temperature_varies()) t_now = hardsphere::state_exchange(*stepper).mv2_sum() / (3.0 * double(atom->natoms));
  t_integral += t_now * dt;
}
