#pragma once
//! Registers `fix hardsphere` and `pair_style hardsphere` on one LAMMPS instance.
namespace LAMMPS_NS {
class LAMMPS;
//! Adds the styles to lmp's Modify::fix_map and Force::pair_map (idempotent).
void hardsphere_register_styles(LAMMPS *lmp);
}  // namespace LAMMPS_NS
