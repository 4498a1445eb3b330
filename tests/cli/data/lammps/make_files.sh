#!/usr/bin/env bash
# Writes the LAMMPS data files of tests/cli/test_lammps_data.py with three LAMMPS releases:
#   bash tests/cli/data/lammps/make_files.sh LMP_HS_2021 LMP_2025 LMP_2026
# (build/plugin/lmp_hs against Debian's 29 Sep 2021 LAMMPS, which has pair_style hardsphere, and
# ~/.cache/hardsphere/lammps-DATE/prefix/bin/lmp). Three atoms of two sizes in a p p f box, with
# velocities, one atom spinning and one with image flags: what write_data writes for each pair
# style (its coefficient sections), 'pair ij', type labels and tilt factors.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
atoms='units lj
atom_style sphere
boundary p p f
region box block 0 6 0 6 0 6
create_box 2 box
create_atoms 1 single 1 1 1
create_atoms 2 single 3 3 3
create_atoms 1 single 4.5 1.2 2
set atom 1 diameter 1.0 density 1.9098593171027443
set atom 2 diameter 1.5 density 1.0
set atom 3 diameter 1.0 density 1.9098593171027443
velocity all create 1.0 4928459 loop geom
set atom 1 omega 0.5 -0.25 3.0
set atom 3 image 1 -2 0'
run() {  # run LMP TAG COMMANDS: the commands after the atoms, files written as TAG_*.data
  printf '%s\n%s\n' "$atoms" "$3" > "$work/in.$2"
  (cd "$work" && "$1" -in "in.$2" -log none -screen none)
  for f in "$work"/*.data; do mv "$f" "$here/$2_$(basename "$f")"; done
}
run "$1" lmp2021 'pair_style hardsphere
pair_coeff * *
write_data hardsphere.data
write_data hardsphere_pairij.data pair ij
pair_style zero 2.0
pair_coeff * *
write_data zero.data'
run "$2" lmp2025 'comm_modify vel yes
pair_style granular
pair_coeff * * hooke 1000.0 50.0 tangential linear_history 1.0 0.5 0.1 damping mass_velocity
write_data granular.data
pair_style zero 2.0
pair_coeff * *
write_data zero_pairij.data pair ij'
run "$3" lmp2026 'pair_style lj/cut 2.5
pair_coeff * * 1.0 1.0
labelmap atom 1 small 2 big
write_data labels_ljcut.data
change_box all triclinic
write_data tilt0.data nocoeff
change_box all xy final 0.5
write_data tilted.data nocoeff'
