#pragma once
//! The LAMMPS API differences between the releases the styles are tested against, in one place.
//! HS_LAMMPS_VERSION is LAMMPS's version.h date as a number (20210929, 20250204, 20260704),
//! set by plugin/CMakeLists.txt. Everything else the styles call is the same in every tested
//! release; the version tables and the message for untested releases are in docs/lammps.md.
#include <string>

#include "comm.h"
#include "error.h"
#include "fix.h"
#include "lammps.h"
#include "modify.h"
#include "utils.h"

#ifndef HS_LAMMPS_VERSION
#error "HS_LAMMPS_VERSION (LAMMPS's version date) must be defined by the build"
#endif

namespace LAMMPS_NS::hs_compat {

//! The LAMMPS releases the styles are tested against (ctest labels lammps and lammps_versions).
constexpr int kTested[] = {20210929, 20250204, 20260704};

//! At `plugin load`: a plugin built against another LAMMPS release is refused (the classes it
//! shares with LAMMPS change layout between releases), an untested release gets a warning.
inline void check_loaded_into(LAMMPS *lmp) {
  const std::string built = std::to_string(HS_LAMMPS_VERSION), running = std::to_string(lmp->num_ver);
  if (lmp->num_ver != HS_LAMMPS_VERSION)
    lmp->error->all(FLERR, "hardsphereplugin.so was built against LAMMPS " + built + " and cannot run in LAMMPS " +
                               running +
                               ", whose classes differ: build it against this LAMMPS (cmake -DHS_LAMMPS_ROOT="
                               "<its install prefix>, see hardsphere's docs/lammps.md)");
  std::string tested;
  bool known = false;
  for (const int v : kTested) {
    tested += (tested.empty() ? "" : ", ") + std::to_string(v);
    known = known || v == lmp->num_ver;
  }
  if (!known && lmp->comm->me == 0)
    lmp->error->warning(FLERR, "hardsphere styles: LAMMPS " + running + " is not among the tested releases (" + tested +
                                   "); run the checks "
                                   "of hardsphere's docs/lammps.md before trusting results");
}

//! Forward communication of a fix's per-atom values (pack/unpack_forward_comm): Comm's
//! forward_comm_fix(Fix *, int) became forward_comm(Fix *, int) in the 17 Feb 2022 release.
inline void forward_comm(Comm *comm, Fix *fix, int size) {
#if HS_LAMMPS_VERSION < 20220217
  comm->forward_comm_fix(fix, size);
#else
  comm->forward_comm(fix, size);
#endif
}

//! Whether a fix whose style matches the regular expression `pattern` is defined (the lookup
//! by style changed name and return type across releases; Modify's fix array did not).
inline bool has_fix_style(Modify *modify, const char *pattern) {
  for (int i = 0; i < modify->nfix; i++)
    if (utils::strmatch(modify->fix[i]->style, pattern)) return true;
  return false;
}

}  // namespace LAMMPS_NS::hs_compat
