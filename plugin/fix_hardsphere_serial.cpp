// fix hardsphere on one rank: the owned atoms are handed to the standalone stepper, which
// resolves periodic images itself, so LAMMPS builds no neighbour list for the fix and every
// result is the standalone stepper's by construction. LAMMPS keeps its own copy of x and v
// (for output, other fixes, restarts): after each step the stepper's state is written back
// through a slot -> local-atom map that is rebuilt only when either side re-orders its atoms.
#include <algorithm>
#include <cmath>
#include <string>

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "fix_hardsphere.h"
#include "modify.h"
#include "hardsphere/errors.hpp"
#include "hardsphere/particles.hpp"
#include "update.h"

using namespace LAMMPS_NS;

void FixHardSphere::serial_setup()
{
  // A fresh stepper at every run: velocity, displace_atoms, set or read_restart may have
  // changed anything between runs.
  const int nlocal = atom->nlocal;
  hardsphere::ParticleSystem sys = empty_system();
  sys.reserve(std::size_t(nlocal));
  for (int i = 0; i < nlocal; i++)
    sys.push_back(std::int64_t(atom->tag[i]), atom->type[i], atom->radius[i], atom->rmass[i],
                  {atom->x[i][0], atom->x[i][1], atom->x[i][2]}, {atom->v[i][0], atom->v[i][1], atom->v[i][2]});
  try {
    hardsphere::validate_and_wrap(sys, "fix hardsphere");  // overlaps, out-of-box atoms
    stepper = new_stepper(sys);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string(e.what()) + "; start from a valid non-overlapping state");
  }
  slots_dirty = true;
}

hardsphere::ParticleSystem FixHardSphere::empty_system() const
{
  hardsphere::ParticleSystem sys;
  for (int d = 0; d < 3; d++) {
    sys.box.lo[d] = domain->boxlo[d], sys.box.hi[d] = domain->boxhi[d];
    sys.box.periodic[d] = domain->periodicity[d] != 0;
  }
  return sys;
}

std::unique_ptr<hardsphere::StepperBase> FixHardSphere::new_stepper(const hardsphere::ParticleSystem &sys) const
{
  hardsphere::StepperConfig cfg;
  cfg.dt = dt;
  cfg.detect = sweep ? hardsphere::Detect::Sweep : hardsphere::Detect::Overlap;
  cfg.max_events_per_step = max_events;
  return hardsphere::make_stepper(sys, cfg);
}

void FixHardSphere::serial_map()
{
  // Which LAMMPS atom each stepper slot is, and the periodic shift between the two copies
  // (LAMMPS and the stepper wrap at different times; a step moves an atom far less than L/2).
  const std::size_t n = stepper->size();
  slot_id.resize(n), slot_local.resize(n), slot_shift.resize(n), slot_pos.resize(n), slot_vel.resize(n);
  stepper->copy_ids(slot_id.data());
  stepper->copy_state(slot_pos.data(), slot_vel.data());
  double **x = atom->x;
  if (n != std::size_t(atom->nlocal))
    error->all(FLERR, "fix hardsphere: atoms were added or removed during a run (" + std::to_string(atom->nlocal) +
                          " now, " + std::to_string(n) + " at its start)");
  // Atomic styles keep no tag -> index map by default (atom_modify map): make one.
  tagint max_tag = 0;
  for (int i = 0; i < atom->nlocal; i++) max_tag = std::max(max_tag, atom->tag[i]);
  tag_local.assign(std::size_t(max_tag) + 1, -1);
  local_slot.resize(std::size_t(atom->nlocal));
  for (int i = 0; i < atom->nlocal; i++) tag_local[std::size_t(atom->tag[i])] = i;
  for (std::size_t k = 0; k < n; k++) {
    const int i = slot_id[k] <= max_tag ? tag_local[std::size_t(slot_id[k])] : -1;
    if (i < 0)
      error->one(FLERR, "fix hardsphere: atom " + std::to_string(slot_id[k]) + " is no longer on this rank");
    slot_local[k] = i;
    local_slot[i] = std::uint32_t(k);
    V3 shift{0, 0, 0};
    for (int d = 0; d < 3; d++)
      if (domain->periodicity[d]) {
        const double len = domain->prd[d];
        shift[d] = len * std::nearbyint((x[i][d] - slot_pos[k][d]) / len);
      }
    slot_shift[k] = shift;
  }
  slot_rebuilds = stepper->counters().rebuilds;
  slots_dirty = false;
}

void FixHardSphere::serial_step()
{
  if (slots_dirty) serial_map();
  const std::size_t n = slot_local.size();
  double **x = atom->x, **v = atom->v;

  // Other fixes may have changed velocities since the last step (a thermostat): take them.
  // v_written holds what this fix wrote, in LAMMPS's order, so the test is one linear pass;
  // with no other fix defined nothing else can have changed them during the run.
  const int nlocal = atom->nlocal;
  bool v_changed = v_written.size() != std::size_t(3 * nlocal);
  for (int i = 0; i < nlocal && !v_changed && modify->nfix > 1; i++)
    v_changed = (v[i][0] != v_written[3 * i]) | (v[i][1] != v_written[3 * i + 1]) | (v[i][2] != v_written[3 * i + 2]);
  if (v_changed) {
    for (std::size_t k = 0; k < n; k++) {
      const double *vi = v[slot_local[k]];
      slot_vel[k] = V3{vi[0], vi[1], vi[2]};
    }
    stepper->set_velocities(slot_vel.data());
  }

  const hardsphere::StepCounters before = stepper->counters();
  stepper->run(1);
  const hardsphere::StepCounters &after = stepper->counters();
  if (after.rebuilds != slot_rebuilds) serial_map();  // new slot order and wrapping
  else stepper->copy_state(slot_pos.data(), slot_vel.data());

  // Position (with its shift) and velocity of a slot side by side, then written in LAMMPS's
  // order: LAMMPS's arrays in sequence, one random read per atom (the two orders are unrelated
  // at short range, and beyond ~10^4 atoms each random access misses the cache).
  slot_out.resize(n);
  for (std::size_t k = 0; k < n; k++) slot_out[k] = {slot_pos[k] + slot_shift[k], slot_vel[k]};
  v_written.resize(std::size_t(3 * nlocal));
  for (int i = 0; i < nlocal; i++) {
    const SlotState &o = slot_out[local_slot[i]];
    x[i][0] = o.x.x, x[i][1] = o.x.y, x[i][2] = o.x.z;
    v[i][0] = v_written[3 * i] = o.v.x;
    v[i][1] = v_written[3 * i + 1] = o.v.y;
    v[i][2] = v_written[3 * i + 2] = o.v.z;
  }

  n_coll_step = double(after.collisions - before.collisions);
  n_coll += n_coll_step;
  for (int k = 0; k < 6; k++) step_virial[k] = after.pair_virial_tensor[k] - before.pair_virial_tensor[k];
  virial_sum += after.pair_virial - before.pair_virial;
  n_wall += double(after.wall_collisions - before.wall_collisions);
  n_unresolved += double(after.unresolved_steps - before.unresolved_steps);
  sim_time += dt;
}
