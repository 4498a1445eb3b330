// lmp_hs: Debian's LAMMPS with the hardsphere styles registered. Command-line flags, input
// handling and exit behaviour are those of `lmp`: the LAMMPS constructor parses the flags, the
// styles are added before the first input line is read.
#include <mpi.h>

#include <cstdio>
#include <exception>

#include "input.h"
#include "lammps.h"
#include "register_styles.h"

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  try {
    auto *lmp = new LAMMPS_NS::LAMMPS(argc, argv, MPI_COMM_WORLD);
    LAMMPS_NS::hardsphere_register_styles(lmp);
    lmp->input->file();
    delete lmp;
  } catch (std::exception &e) {
    std::fprintf(stderr, "lmp_hs: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return 0;
}
