// C entry point for python3-lammps users:
//   lib = ctypes.CDLL("libhardsphere_lammps.so"); lib.hs_register_styles(ctypes.c_void_p(lmp.lmp))
// after which `lmp.command("fix 1 all hardsphere")` etc. work on that LAMMPS instance.
#include "lammps.h"
#include "register_styles.h"

extern "C" int hs_register_styles(void *handle) {
  if (!handle) return 1;
  LAMMPS_NS::hardsphere_register_styles(static_cast<LAMMPS_NS::LAMMPS *>(handle));
  return 0;
}
