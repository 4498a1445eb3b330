// lmp_hs: Debian's LAMMPS with the hardsphere styles registered. Command-line flags, input
// handling and exit behaviour are those of `lmp`: the LAMMPS constructor parses the flags, the
// styles are added before the first input line is read.
#define LAMMPS_LIB_MPI
#include <dlfcn.h>
#include <mpi.h>

#include <cstdio>
#include <exception>

#include "input.h"
#include "lammps.h"
#include "library.h"
#include "register_styles.h"

namespace {

//! The file the dynamic linker took liblammps from (LD_LIBRARY_PATH may name another LAMMPS's).
const char *loaded_library() {
  Dl_info info{};
  return dladdr(reinterpret_cast<void *>(&lammps_version), &info) && info.dli_fname ? info.dli_fname : "?";
}

}  // namespace

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  try {
    // The instance is made inside liblammps and its version asked through the C interface, both
    // independent of the class layouts: the styles share those with the release they were built
    // against, and another release's library would crash them without a word.
    void *handle = lammps_open(argc, argv, MPI_COMM_WORLD, nullptr);
    const int found = handle ? lammps_version(handle) : 0;
    if (found != HS_LAMMPS_VERSION) {
      int me = 0;
      MPI_Comm_rank(MPI_COMM_WORLD, &me);
      if (me == 0)
        std::fprintf(stderr,
                     "lmp_hs: error: built against LAMMPS %d, but the LAMMPS library loaded is %d (%s), whose "
                     "classes differ; run lmp_hs with the library it was built against (check LD_LIBRARY_PATH), "
                     "or load hardsphereplugin.so built for that LAMMPS into its own lmp (docs/lammps.md)\n",
                     HS_LAMMPS_VERSION, found, loaded_library());
      MPI_Finalize();
      return 1;
    }
    auto *lmp = static_cast<LAMMPS_NS::LAMMPS *>(handle);
    LAMMPS_NS::hardsphere_register_styles(lmp);
    lmp->input->file();
    lammps_close(handle);
  } catch (std::exception &e) {
    std::fprintf(stderr, "lmp_hs: %s\n", e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return 0;
}
