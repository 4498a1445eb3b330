// The re-run of a step for all atoms at once (GhostPath::step_globally): the start state gathered
// over MPI, one stepper over it on every rank, each rank keeping its own atoms.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "ghost_path.h"
#include "hardsphere/particles.hpp"
#include "lammps_atoms.h"

using namespace LAMMPS_NS;
using hardsphere::Vec3d;

StepTotals GhostPath::step_globally(bool check, const std::string &source, const std::string &hint) {
  // Re-run this step for all atoms at once with one standalone stepper (the same algorithm,
  // so the result a complete ghost shell gives), on every rank from the gathered start state;
  // each rank keeps its own atoms. Rare.
  const int nlocal = atom->nlocal;
  const bool rough = physics_.rough();
  const std::vector<double> mine = owned_atom_records(atom, rough);  // x and v still the step's start
  const int nprocs = comm->nprocs;
  int count = int(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(nprocs)), displs(static_cast<std::size_t>(nprocs), 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int r = 1; r < nprocs; r++) displs[std::size_t(r)] = displs[std::size_t(r - 1)] + counts[std::size_t(r - 1)];
  std::vector<double> all(std::size_t(displs.back() + counts.back()));
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);

  hardsphere::ParticleSystem sys = records_to_system(all, lammps_box(domain), rough);
  if (check) {  // validates and wraps, with the serial path's overlap tolerance
    try {
      hardsphere::validate_and_wrap(sys, source, nullptr, hardsphere::rounding_epsilon(hardsphere::Precision::Double));
    } catch (const std::exception &e) {
      error->all(FLERR, std::string(e.what()) + "; " + hint);
    }
  } else {
    hardsphere::wrap_periodic(sys);
  }
  hardsphere::ParticleSystem out;
  hardsphere::StepCounters c;
  try {
    auto global = hardsphere::make_stepper(sys, physics_, config_);
    auto &exch = hardsphere::state_exchange(*global);
    exch.set_sphere_virial(virial_rows_ != nullptr);
    global->run(1);
    out = global->state();
    c = global->counters();
    if (virial_rows_) take_owned_virial(exch);
  } catch (const std::exception &e) {
    error->all(FLERR, std::string("fix hardsphere: re-running a step for all atoms failed: ") + e.what());
  }

  // Owned atoms move by the stepper's displacement from where they started (LAMMPS keeps its
  // own periodic wrapping and image flags).
  double **x = atom->x, **v = atom->v;
  for (int i = 0; i < nlocal; i++) {
    const auto it = std::lower_bound(out.id.begin(), out.id.end(), std::int64_t(atom->tag[i]));
    const std::size_t k = std::size_t(it - out.id.begin());
    const Vec3d start{x[i][0], x[i][1], x[i][2]};
    Vec3d d = out.pos[k] - start;
    for (int a = 0; a < 3; a++)
      if (sys.box.periodic[a]) d[a] -= sys.box.length(a) * std::nearbyint(d[a] / sys.box.length(a));
    const Vec3d p = start + d;
    x[i][0] = p.x, x[i][1] = p.y, x[i][2] = p.z;
    v[i][0] = out.vel[k].x, v[i][1] = out.vel[k].y, v[i][2] = out.vel[k].z;
    if (rough)
      atom->omega[i][0] = out.omega[k].x, atom->omega[i][1] = out.omega[k].y, atom->omega[i][2] = out.omega[k].z;
  }
  StepTotals t;
  t.rerun = true;
  if (comm->me == 0) {  // the stepper counted every atom: rank 0 reports the totals
    static_cast<hardsphere::WeightedCollisionTotals &>(t) = hardsphere::collision_totals<double>(c);
    t.unresolved = double(c.unresolved_steps);
  }
  return t;
}

void GhostPath::take_owned_virial(hardsphere::StateExchange &exch) {
  // The engine holds every atom: this rank's shares go to its rows, found by tag.
  std::vector<std::int64_t> ids(exch.size());
  exch.copy_ids(ids.data());
  std::int64_t max_id = 0;
  for (const std::int64_t id : ids) max_id = std::max(max_id, id);
  std::vector<std::uint32_t> row_of_id(std::size_t(max_id) + 1, hardsphere::StateExchange::kNoRow);
  for (int i = 0; i < atom->nlocal; i++) row_of_id[std::size_t(atom->tag[i])] = std::uint32_t(i);
  std::vector<std::uint32_t> dest(ids.size());
  for (std::size_t k = 0; k < ids.size(); k++) dest[k] = row_of_id[std::size_t(ids[k])];
  std::fill(virial_rows_, virial_rows_ + 6 * atom->nlocal, 0.0);
  exch.take_sphere_virial(dest.data(), virial_scale_, virial_rows_);
}
