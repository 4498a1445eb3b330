#!/usr/bin/env python3
"""python3-lammps + ctypes: load libhardsphere_lammps.so (argv[1]), register the styles on a LAMMPS
handle and run a small hard-sphere gas; then check the entry of hardsphereplugin.so (argv[2]). Skipped (exit 0 with a note) without python3-lammps."""
import ctypes
import sys

try:
    from lammps import lammps
except ImportError:
    print("skip: python3-lammps is not installed")
    sys.exit(0)

lib = ctypes.CDLL(sys.argv[1])
lib.hs_register_styles.argtypes = [ctypes.c_void_p]
lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
assert lib.hs_register_styles(lmp.lmp) == 0
for cmd in """units lj
atom_style sphere
lattice fcc 0.573
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 box
set type 1 diameter 1.0
set type 1 mass 1.0
velocity all create 1.0 7 dist gaussian
pair_style hardsphere
pair_coeff * *
neighbor 0.5 bin
neigh_modify every 1 delay 0 check yes
timestep 0.01
fix hs all hardsphere
thermo_style custom step ke f_hs[1]
run 200""".splitlines():
    lmp.command(cmd)
coll = lmp.extract_fix("hs", 0, 1, 0)
ke = lmp.get_thermo("ke")
print(f"collisions {coll:.0f}, ke {ke}")
ok = coll > 100 and lmp.get_natoms() == 256
lmp.close()

# The PLUGIN-package entry (Debian's LAMMPS has no `plugin load`): call lammpsplugin_init of
# hardsphereplugin.so with a live LAMMPS (it checks the version it runs in) and a recording
# register function, and check every style is offered.
if len(sys.argv) > 2:
    class Plugin(ctypes.Structure):
        _fields_ = [("version", ctypes.c_char_p), ("style", ctypes.c_char_p), ("name", ctypes.c_char_p),
                    ("info", ctypes.c_char_p), ("author", ctypes.c_char_p), ("creator", ctypes.c_void_p),
                    ("handle", ctypes.c_void_p)]
    seen = []
    REG = ctypes.CFUNCTYPE(None, ctypes.POINTER(Plugin), ctypes.c_void_p)
    reg = REG(lambda p, lmp: seen.append((p.contents.style.decode(), p.contents.name.decode(), bool(p.contents.creator))))
    plug = ctypes.CDLL(sys.argv[2], mode=ctypes.RTLD_GLOBAL)
    host = lammps(cmdargs=["-log", "none", "-screen", "none"])
    plug.lammpsplugin_init.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    plug.lammpsplugin_init(host.lmp, None, ctypes.cast(reg, ctypes.c_void_p))
    host.close()
    print("plugin registers", seen)
    ok = ok and sorted(seen) == [("fix", "hardsphere", True), ("fix", "wall/hardsphere", True),
                                 ("fix", "wall/hardsphere/region", True), ("pair", "hardsphere", True)]
sys.exit(0 if ok else 1)
