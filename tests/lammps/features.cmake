# The LAMMPS checks, FEATURE or FEATURE:GROUP,GROUP,... (the groups of FEATURE.yaml), one list for
# the Debian 12 tests (CMakeLists.txt, a test per group) and the further releases (versions.cmake,
# a test per feature).
set(HS_LAMMPS_FEATURES
    identical:gas,ghosts,walls conservation errors:setup,forces,atoms,runs
    runs:restart,between,unwrapped,pre_no,half_box,rerun defaults:neighbour,newton,allowed,mixture
    outputs:pressure,timing,stress_atom,walls,temperature restitution freeze rough:identical,energy,ghosts gravity units:styles,scales
    readers:groups,computes,commands pour shapes regions)
