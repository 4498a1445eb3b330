#include "part_timer.h"

#include <mpi.h>

#include <cstdio>
#include <string>

#include "lammps.h"
#include "utils.h"

using namespace LAMMPS_NS;

void PartTimer::report(LAMMPS *lmp, MPI_Comm world, long steps) const {
  if (!on_) return;
  std::array<double, kParts> lo{}, sum{}, hi{};
  MPI_Allreduce(total_.data(), lo.data(), kParts, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(total_.data(), sum.data(), kParts, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(total_.data(), hi.data(), kParts, MPI_DOUBLE, MPI_MAX, world);
  int me = 0, nprocs = 1;
  MPI_Comm_rank(world, &me);
  MPI_Comm_size(world, &nprocs);
  if (me != 0) return;
  static const char *names[kParts] = {
      "steps (the stepper)",
      "making the stepper again (re-neighbouring)",
      "following LAMMPS's re-neighbouring",
      "writing LAMMPS's x and v",
      "largest move (when to re-neighbour)",
      "setting ghost copies from their owners",
      "owner check (incl. waiting for ranks)",
      "steps re-run for all atoms",
  };
  std::string out = "fix hardsphere timing over " + std::to_string(steps) + " steps (s; min / avg / max over " +
                    std::to_string(nprocs) + (nprocs == 1 ? " rank):\n" : " ranks):\n");
  char line[160];
  for (int p = 0; p < kParts; p++) {
    if (hi[p] == 0.0) continue;  // parts the run's path does not have
    std::snprintf(line, sizeof(line), "  %-44s %10.4g %10.4g %10.4g\n", names[p], lo[p], sum[p] / nprocs, hi[p]);
    out += line;
  }
  utils::logmesg(lmp, out);
}
