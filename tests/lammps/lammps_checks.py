#!/usr/bin/env python3
"""LAMMPS styles (fix hardsphere, pair_style hardsphere) against the standalone stepper.

Usage: lammps_checks.py CHECK --lmp PATH --hs PATH [--mpirun PATH] [--np N]
CHECK: identical | conservation | errors | runs | defaults | outputs | restitution | gravity | units |
       decompositions (MPI: its own rank counts, --np ignored)
Each check builds its own initial state with `hardsphere run --write-data` in a temporary dir.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


def read_data(path):
    """Box lengths, positions and velocities sorted by atom id from a LAMMPS data file."""
    box, atoms, vels, sec = [], {}, {}, None
    for line in open(path):
        s = line.split("#")[0].split()
        if line.strip().startswith("Atoms"):
            sec = "a"
            continue
        if line.strip().startswith("Velocities"):
            sec = "v"
            continue
        if len(s) == 4 and s[2] in ("xlo", "ylo", "zlo"):
            box.append(float(s[1]) - float(s[0]))
            continue
        if not s:
            continue
        if sec == "a" and len(s) >= 7:
            atoms[int(s[0])] = [float(t) for t in s[4:7]]
        elif sec == "v" and len(s) >= 4:
            vels[int(s[0])] = [float(t) for t in s[1:4]]
        else:
            sec = None
    ids = sorted(atoms)
    return np.array(box), np.array([atoms[i] for i in ids]), np.array([vels[i] for i in ids])


def state_difference(ref_path, other_path, periodic=(True, True, True)):
    """Largest |dx| (minimum image on periodic axes) and |dv| between two data files' atoms, by id."""
    box, xs, vs = read_data(ref_path)
    _, xo, vo = read_data(other_path)
    dx = xo - xs
    per = np.array(periodic)
    dx[:, per] -= box[per] * np.round(dx[:, per] / box[per])
    return np.abs(dx).max(), np.abs(vo - vs).max()


def run_lmp(args, script, cwd, np_=1, expect_ok=True):
    inp = os.path.join(cwd, "in.test")
    with open(inp, "w") as f:
        f.write(script)
    cmd = [args.lmp, "-in", inp, "-log", "none", "-echo", "none"]
    if np_ > 1:
        cmd = [args.mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(np_)] + cmd
    p = subprocess.run(cmd, cwd=cwd, env=ENV, capture_output=True, text=True, timeout=300)
    out = p.stdout + p.stderr
    if expect_ok and p.returncode != 0:
        sys.exit(f"lmp_hs failed ({p.returncode}):\n{out[-3000:]}")
    return p.returncode, out


def thermo_blocks(out):
    """Every thermo block (one per run or rerun): lists of rows as dicts of floats."""
    blocks, head = [], None
    for line in out.splitlines():
        s = line.split()
        if s and s[0] == "Step":
            head = s
            blocks.append([])
        elif head and len(s) == len(head):
            try:
                blocks[-1].append(dict(zip(head, map(float, s))))
            except ValueError:
                head = None
        elif head and s and s[0] == "Loop":
            head = None
    return blocks


def thermo(out):
    """Rows of the last thermo block as dicts of floats."""
    blocks = thermo_blocks(out)
    return blocks[-1] if blocks else []


def standalone(args, cwd, *opts):
    p = subprocess.run([args.hs, "run", *opts, "--json", "-"], cwd=cwd, capture_output=True, text=True, check=True)
    return json.loads(p.stdout)


HEADER = """units lj
atom_style sphere
boundary p p p
read_data {data}
pair_style hardsphere
pair_coeff * *
neighbor {skin} bin
neigh_modify every 1 delay 0 check yes
timestep {dt}
fix hs all hardsphere
"""


MOVER = """from lammps import lammps


def move(ptr):
    lmp = lammps(ptr=ptr)
    x = lmp.numpy.extract_atom("x")
    n = lmp.extract_global("nlocal")
    {body}
"""


def python_mover(d, body):
    """The commands for a fix python/invoke that runs `body` on this rank's atoms' x[:n] every 10
    steps at the end of the step (a fix that moves atoms and is not known to the fix)."""
    with open(os.path.join(d, "mover.py"), "w") as f:
        f.write(MOVER.format(body=body))
    return "python move source mover.py\nfix p all python/invoke 10 end_of_step move\n"


def check(cond, msg):
    print(("ok:   " if cond else "FAIL: ") + msg)
    return bool(cond)


def gas_reference(args, d):
    """The 1000-atom gas at phi 0.3 (init.data in d) and the standalone's 200 steps of 0.01 on it."""
    standalone(args, d, "--n", "1000", "--phi", "0.3", "--steps", "0", "--write-data", "init.data")
    return standalone(args, d, "--read-data", "init.data", "--steps", "200", "--dt", "0.01")


def pressure_run(columns, units="lj"):
    """200 steps of the gas with thermo `columns` and LAMMPS's press averaged over them (f_pav)."""
    return HEADER.format(data="init.data", skin=0.5, dt=0.01).replace("units lj", f"units {units}") + f"""
compute p all pressure thermo_temp
fix pav all ave/time 1 200 200 c_p
thermo_style custom {columns} f_pav
thermo_modify format float %.17g
thermo 200
run 200
"""

def identical(args):
    """Same state, same dt: the fix reproduces the stepper's collisions. The resolver, its
    ordering and tie-breaks are shared; positions differ only by round-off (LAMMPS wraps
    positions at its own rebuilds and shifts ghosts by the box length, the stepper applies image
    shifts per pair), which chaotic dynamics amplify to ~1e-9 over 200 steps at phi 0.3. The
    bound 1e-6 leaves room; a different collision would show up as an O(0.1) difference."""
    ok = True
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "1000", "--phi", "0.3", "--steps", "0", "--write-data", "init.data")
        ref = standalone(args, d, "--read-data", "init.data", "--steps", "200", "--dt", "0.01", "--write-data", "sa.data")
        script = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """
compute p all pressure thermo_temp
fix pav all ave/time 1 200 200 c_p
thermo_style custom step ke f_hs[1] f_hs[3] f_hs[6] f_pav
thermo_modify format float %.17g
thermo 200
run 200
write_data lmp.data
"""
        rc, out = run_lmp(args, script, d, np_=args.np)
        last = thermo(out)[-1]
        tag = f"np={args.np}: "
        ok &= check(last["f_hs[1]"] == ref["collisions"], tag + f"collisions {last['f_hs[1]']:.0f} == standalone {ref['collisions']}")
        ok &= check(abs(last["f_hs[3]"] / ref["pair_virial"] - 1) < 1e-9, tag + f"virial {last['f_hs[3]']} vs {ref['pair_virial']}")
        dx, dv = state_difference(os.path.join(d, "sa.data"), os.path.join(d, "lmp.data"))
        ok &= check(dx < 1e-6 and dv < 1e-6, tag + f"final state max |dx| {dx:.2e}, max |dv| {dv:.2e} < 1e-6")
        ok &= check(last["f_hs[6]"] == 0, tag + "every ghost agreed with its owner (no step re-run for all atoms)")
        # Thermo pressure averaged over every step = n T + W/(3 V t): the standalone's pressure.
        ok &= check(abs(last["f_pav"] / ref["pressure"] - 1) < 1e-6, tag + f"<press> {last['f_pav']:.10g} vs standalone {ref['pressure']:.10g}")

        # `newton off` (recommended in docs/lammps.md: LAMMPS then skips its reverse communication
        # of forces) changes LAMMPS's ghost bookkeeping, not the result.
        script_n = script.replace("units lj", "units lj\nnewton off").replace("write_data lmp.data", "write_data lmp_n.data")
        rc, out = run_lmp(args, script_n, d, np_=args.np)
        last_n = thermo(out)[-1]
        dxn, dvn = state_difference(os.path.join(d, "sa.data"), os.path.join(d, "lmp_n.data"))
        ok &= check(last_n["f_hs[1]"] == ref["collisions"] and dxn < 1e-6 and dvn < 1e-6,
                    tag + f"newton off: collisions {last_n['f_hs[1]']:.0f} == standalone {ref['collisions']}, "
                    f"max |dx| {dxn:.2e}, max |dv| {dvn:.2e} < 1e-6")

        if args.np == 1:
            ok &= identical_big_sphere(args, d, tag)

        # The owned + ghost path (MPI's; 'path ghosts' forces it in serial). On one rank its
        # stepper holds every atom and no ghost: the standalone's collisions.
        script_p = HEADER.format(data="init.data", skin=0.5, dt=0.01).replace(
            "fix hs all hardsphere", "fix hs all hardsphere path ghosts") + """
thermo_style custom step ke f_hs[1] f_hs[6]
thermo 200
run 200
"""
        rc, out = run_lmp(args, script_p, d, np_=args.np)
        n_p = thermo(out)[-1]["f_hs[1]"]
        ok &= check(n_p == ref["collisions"], tag + f"path ghosts: collisions {n_p:.0f} == standalone {ref['collisions']}")
        # A ghost shell of at most two contact distances cannot hold the partners of the ghosts
        # an owned atom meets: refused, naming the remedy.
        rc, out = run_lmp(args, script_p.replace("fix hs all hardsphere path ghosts",
                                                 "comm_modify cutoff 1.5\nfix hs all hardsphere path ghosts ghost user"),
                          d, np_=args.np, expect_ok=False)
        ok &= check(rc != 0 and "does not exceed twice the largest contact distance" in out and
                    "comm_modify cutoff" in out, tag + "a ghost shell of 1.5 contact distances is refused")
        # A thin shell (2.3 contact distances) with long steps in a dense gas: collision chains
        # run past it within a step, ghost copies disagree with their owners and those steps are
        # re-run for all atoms (on 2 ranks); energy stays exact, the collision rate the stepper's.
        standalone(args, d, "--n", "1000", "--phi", "0.45", "--steps", "0", "--write-data", "dense.data")
        ref_d = standalone(args, d, "--read-data", "dense.data", "--steps", "200", "--dt", "0.02")
        script_g = HEADER.format(data="dense.data", skin=0.5, dt=0.02).replace(
            "fix hs all hardsphere", "comm_modify cutoff 2.3\nfix hs all hardsphere path ghosts ghost user") + """
thermo_style custom step ke f_hs[1] f_hs[6] f_hs[7]
thermo_modify format float %.17g
thermo 200
run 200
"""
        rc, out = run_lmp(args, script_g, d, np_=args.np)
        rows_g = thermo(out)
        last_g = rows_g[-1]
        if args.np > 1:
            ok &= check(last_g["f_hs[6]"] > 0, tag + f"thin ghost shell: {last_g['f_hs[6]']:.0f} steps re-run for all atoms (> 0)")
        ok &= check(abs(last_g["f_hs[1]"] / ref_d["collisions"] - 1) < 0.005,
                    tag + f"thin ghost shell: collisions {last_g['f_hs[1]']:.0f} within 0.5% of standalone {ref_d['collisions']}")
        ok &= check(abs(last_g["KinEng"] / rows_g[0]["KinEng"] - 1) < 1e-12, tag + "thin ghost shell: energy kept to 1e-12")

        # detect sweep (whole-step sweep instead of the end-of-step overlap test)
        ref_s = standalone(args, d, "--read-data", "init.data", "--steps", "200", "--dt", "0.01", "--detect", "sweep")
        script_s = HEADER.format(data="init.data", skin=0.5, dt=0.01).replace(
            "fix hs all hardsphere", "fix hs all hardsphere detect sweep") + """
thermo_style custom step ke f_hs[1]
thermo 200
run 200
"""
        rc, out = run_lmp(args, script_s, d, np_=args.np)
        n_s = thermo(out)[-1]["f_hs[1]"]
        ok &= check(n_s == ref_s["collisions"], tag + f"detect sweep: collisions {n_s:.0f} == standalone {ref_s['collisions']}")

        # Binary mixture (diameters 1 and 0.6, masses by volume) between walls at z = 0, 10:
        # the unequal-mass kernel and wall reflection, state written by LAMMPS, read by both.
        gen = """units lj
atom_style sphere
boundary p p f
lattice fcc 0.5
region box block 0 5 0 5 0 5
create_box 2 box
region inner block INF INF INF INF 0.2 4.8
create_atoms 1 region inner
set type 1 type/fraction 2 0.3 2934
set type 1 diameter 1.0
set type 2 diameter 0.6
set type 1 mass 1.0
set type 2 mass 0.216
velocity all create 1.0 3049 dist gaussian mom yes
write_data poly.data
"""
        run_lmp(args, gen, d)
        ref = standalone(args, d, "--read-data", "poly.data", "--boundary", "p,p,w", "--steps", "200", "--dt", "0.005",
                         "--write-data", "sa_poly.data")
        script = HEADER.format(data="poly.data", skin=0.5, dt=0.005).replace("boundary p p p", "boundary p p f") + """
thermo_style custom step ke f_hs[1] f_hs[3] f_hs[5]
thermo_modify format float %.17g
thermo 200
run 200
write_data lmp_poly.data
"""
        rc, out = run_lmp(args, script, d, np_=args.np)
        last = thermo(out)[-1]
        ok &= check(last["f_hs[1]"] == ref["collisions"] and last["f_hs[5]"] == ref["wall_collisions"],
                    tag + f"mixture+walls: collisions {last['f_hs[1]']:.0f} == {ref['collisions']}, "
                    f"wall bounces {last['f_hs[5]']:.0f} == {ref['wall_collisions']}")
        dx, dv = state_difference(os.path.join(d, "sa_poly.data"), os.path.join(d, "lmp_poly.data"),
                                  periodic=(True, True, False))  # z has walls: no wrapping
        ok &= check(dx < 1e-6 and dv < 1e-6, tag + f"mixture+walls: max |dx| {dx:.2e}, max |dv| {dv:.2e} < 1e-6")

        # Dense gas (phi 0.4) between walls on two axes, on the owned + ghost path even at np 1:
        # spheres sent into a wall by a collision meet neighbours on the way, and the drift's
        # mirrors are undone so the resolver bounces them in time order. Same collisions and
        # bounces as the stepper; the second 'run 0' re-checks that no pair overlaps.
        standalone(args, d, "--n", "3000", "--phi", "0.4", "--boundary", "p,w,w", "--seed", "2", "--steps", "0",
                   "--write-data", "dense_walls.data")
        ref = standalone(args, d, "--read-data", "dense_walls.data", "--boundary", "p,w,w", "--steps", "100",
                         "--dt", "0.01")
        script = (HEADER.format(data="dense_walls.data", skin=0.5, dt=0.01).replace("boundary p p p", "boundary p f f")
                  .replace("fix hs all hardsphere", "fix hs all hardsphere path ghosts") + """
thermo_style custom step ke f_hs[1] f_hs[5]
thermo 100
run 100
run 0
""")
        rc, out = run_lmp(args, script, d, np_=args.np)
        last = thermo(out)[-1]
        ok &= check(last["f_hs[1]"] == ref["collisions"] and last["f_hs[5]"] == ref["wall_collisions"],
                    tag + f"dense walls (ghost path): collisions {last['f_hs[1]']:.0f} == {ref['collisions']}, "
                    f"wall bounces {last['f_hs[5]']:.0f} == {ref['wall_collisions']}, no overlap after the run")
    return ok


def identical_big_sphere(args, d, tag):
    """A big heavy sphere (diameter 6, mass 1000) in 2000 unit spheres: the serial fix runs the
    stepper, with its own pass for big spheres, and reproduces the standalone collision for collision."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    subprocess.run([sys.executable, "-m", "compare.big_sphere_scene", "--n", "2000", "--phi", "0.2", "--big", "1",
                    "--big-diameter", "6", "--big-mass", "1000", "--out", "big.data"], cwd=d, check=True,
                   capture_output=True, env=dict(os.environ, PYTHONPATH=root))
    ref = standalone(args, d, "--read-data", "big.data", "--steps", "200", "--dt", "0.01", "--write-data", "sa_big.data")
    script = HEADER.format(data="big.data", skin=0.5, dt=0.01) + """
thermo_style custom step ke f_hs[1]
thermo_modify format float %.17g
thermo 200
run 200
write_data lmp_big.data
"""
    rc, out = run_lmp(args, script, d)
    last = thermo(out)[-1]
    dx, dv = state_difference(os.path.join(d, "sa_big.data"), os.path.join(d, "lmp_big.data"))
    return check(last["f_hs[1]"] == ref["collisions"] and dx < 1e-6 and dv < 1e-6,
                 tag + f"big sphere: collisions {last['f_hs[1]']:.0f} == standalone {ref['collisions']}, "
                 f"max |dx| {dx:.2e}, max |dv| {dv:.2e} < 1e-6")


def conservation(args):
    """10^4 steps: energy to 1e-10 relative, momentum to round-off, no overlap left."""
    ok = True
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "256", "--phi", "0.3", "--steps", "0", "--write-data", "init.data")
        script = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """
variable px equal vcm(all,x)*mass(all)
variable py equal vcm(all,y)*mass(all)
variable pz equal vcm(all,z)*mass(all)
thermo_style custom step ke v_px v_py v_pz f_hs[1] f_hs[6]
thermo_modify format float %.17g
thermo 2000
run 10000
write_data lmp.data
"""
        rc, out = run_lmp(args, script, d, np_=args.np)
        rows = thermo(out)
        e0, e1 = rows[0]["KinEng"], rows[-1]["KinEng"]
        tag = f"np={args.np}: "
        ok &= check(rows[-1]["f_hs[1]"] > 10000, tag + f"{rows[-1]['f_hs[1]']:.0f} collisions")
        ok &= check(abs(e1 / e0 - 1) < 1e-10, tag + f"energy drift {abs(e1 / e0 - 1):.2e} < 1e-10")
        p = max(abs(r[k]) for r in rows for k in ("v_px", "v_py", "v_pz"))
        ok &= check(p < 1e-10, tag + f"momentum max |P| {p:.2e} < 1e-10 (256 atoms, |v|~1.7)")
        box, x, _ = read_data(os.path.join(d, "lmp.data"))
        dr = x[:, None, :] - x[None, :, :]
        dr -= box * np.round(dr / box)
        r = np.sqrt((dr ** 2).sum(-1)) + np.eye(len(x)) * 10
        ok &= check(r.min() > 1 - 1e-9, tag + f"no overlap: min distance {r.min():.12f}")
    return ok


WALLS = """units lj
atom_style sphere
boundary p p f
lattice fcc 0.5
region box block 0 4 0 4 0 4
create_box 1 box
region inner block INF INF INF INF 0.2 3.8
create_atoms 1 region inner
set type 1 diameter 1.0
set type 1 mass 1.0
velocity all create 1.0 87287 dist gaussian mom yes
pair_style hardsphere
pair_coeff * *
neighbor 0.5 bin
timestep 0.01
fix hs all hardsphere
"""


def errors(args):
    """Bad inputs end with a LAMMPS error naming what to change: the offending command or value
    and the fix's advice, exactly. Under --np 2 the cases marked for MPI (error->all must stop
    every rank the same way)."""
    ok = True
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "100", "--phi", "0.2", "--steps", "0", "--write-data", "init.data")
        base = HEADER.format(data="init.data", skin=0.5, dt=0.01)
        force = ("adds or acts on forces, but hard spheres have no forces (fix hardsphere moves them by collisions "
                 "only), so it would have no effect: remove it")
        thermostat = " (thermostat with an end-of-step fix instead, e.g. temp/berendsen or temp/rescale)"
        wall = ("is a wall fix, which hard spheres would not feel (they have no forces): walls come from the box, use "
                "'boundary f' on that axis (spheres bounce off fixed faces) and remove 'fix w'")
        inserts = ("inserts or deletes atoms during a run, but fix hardsphere follows one set of atoms through a "
                   "run: remove it and add or delete atoms between runs (create_atoms, delete_atoms)")
        region = "region ins block 0.5 3.5 0.5 3.5 2 3.5\n"
        # name: (script, exact phrase in the ERROR line, run on 2 ranks too)
        cases = {
            "wrong atom style": ("units lj\natom_style atomic\nregion b block 0 5 0 5 0 5\ncreate_box 1 b\n"
                                 "create_atoms 1 single 1 1 1\nmass 1 1\npair_style hardsphere\npair_coeff * * 1.0\n"
                                 "fix hs all hardsphere\nrun 1\n", "use 'atom_style sphere'", False),
            "pair without fix": (base.replace("fix hs all hardsphere\n", "fix nve all nve/sphere\n") + "run 1\n",
                                 "add 'fix ID all hardsphere'", False),
            "fix without pair": (base.replace("pair_style hardsphere\npair_coeff * *\n", "") + "run 1\n",
                                 "needs 'pair_style hardsphere'", False),
            "another integrator": (base + "fix nve all nve/sphere\nrun 1\n",
                                   "fix hardsphere is the time integrator: remove fix nve (nve/sphere)", False),
            "overlapping atoms": (base + "set atom 1 x 0.0 y 0.0 z 0.0\nset atom 2 x 0.3 y 0.0 z 0.0\nrun 1\n",
                                  "overlap", True),
            # Grown diameters (the compression protocol) must be checked at the next run's start too.
            "overlap after set diameter": (base + "run 10\nset group all diameter 1.3\nrun 10\n",
                                           "start from a valid non-overlapping state", True),
            "atom outside a fixed wall": (WALLS + "set atom 1 z 0.25\nrun 1\n",
                                          "fix hardsphere: atom 1: z = 0.25 with radius 0.5 is outside the "
                                          "wall-bounded box [0, 8]; start from a valid non-overlapping state", True),
            "bonds": ("units lj\natom_style hybrid sphere bond\nlattice sc 0.2\nregion b block 0 5 0 5 0 5\n"
                      "create_box 1 b bond/types 1 extra/bond/per/atom 6\ncreate_atoms 1 region b\n"
                      "set type 1 mass 1.0\nset type 1 diameter 1.0\nvelocity all create 1.0 4928 mom yes\n"
                      "bond_style harmonic\nbond_coeff 1 100.0 1.7\npair_style hardsphere\npair_coeff * *\n"
                      "neighbor 1.0 bin\nfix hs all hardsphere\ncreate_bonds many all all 1 1.6 1.8\nrun 1\n",
                      "fix hardsphere: the system has 375 bonds (bond_style harmonic), but hard spheres interact only "
                      "by collisions: bonded forces would not act and bonded pairs would still collide", True),
            "dt too large": (HEADER.format(data="init.data", skin=0.5, dt=0.2) + "run 1\n", "timestep too large", False),
            "diameter too small": (base + "pair_coeff * * 0.5\nrun 1\n", "raise that pair_coeff diameter", False),
            "changing box": (base + "fix d all deform 1 x scale 1.1\nrun 1\n",
                             "fix hardsphere needs a fixed box: fix d (deform) changes it", False),
            "comm mode multi": (base.replace("neighbor 0.5 bin", "neighbor 0.5 multi\ncomm_modify mode multi").replace(
                "fix hs all hardsphere", "fix hs all hardsphere path ghosts") + "run 1\n",
                                "fix hardsphere: 'comm_modify mode multi' gives each atom type its own, thinner ghost "
                                "shell; use 'comm_modify mode single' on more than one rank or with 'path ghosts'", True),
            "fix defined before run pre no": (base + "run 1\nunfix hs\nfix hs all hardsphere\nrun 1 pre no\n",
                                              "fix hardsphere was defined after the last run's setup, which 'run "
                                              "... pre no' skips", True),
            "fix added before run pre no": (base + "run 1\nfix t all temp/rescale 10 1.0 1.0 0.1 1.0\nrun 1 pre no\n",
                                            "fix hardsphere: fixes were added, removed or replaced since the last "
                                            "run's setup", True),
            "timestep 0": (base + "timestep 0\nrun 1\n",
                           "fix hardsphere: 'timestep 0': the time step must be positive and finite", True),
            "negative timestep between pieces": (base + "run 10 pre no every 5 'timestep -0.01'\n",
                                                 "fix hardsphere: 'timestep -0.01': the time step must be positive", True),
            "run pre no after rerun": (base + "run 10\nwrite_dump all custom s.dump id x y z\n"
                                       "rerun s.dump dump x y z\nrun 1 pre no\n",
                                       "fix hardsphere: 'run ... pre no' right after 'rerun' would start from the "
                                       "last snapshot without checking it", True),
            "neighbour exclusion": (base + "group half id <= 50\nneigh_modify exclude group half all\nrun 1\n",
                                    "fix hardsphere: 'neigh_modify exclude' is not supported (every pair of hard "
                                    "spheres collides); use 'neigh_modify exclude none'", True),
            # Fixes that add or act on forces would have no effect: refused, named, with the reason.
            "fix gravity along a periodic axis": (base + "fix g all gravity 1.0 vector 0 0 -1\nrun 1\n",
                                                  "fix hardsphere: fix gravity has a component along the periodic axis z, "
                                                  "which would accelerate the atoms without end: use 'boundary f' on "
                                                  "that axis", True),
            "fix viscous": (base + "fix v all viscous 0.1\nrun 1\n",
                            "fix hardsphere: fix v (viscous) " + force + thermostat, True),
            "fix langevin": (base + "fix l all langevin 1.0 1.0 1.0 48279\nrun 1\n",
                             "fix hardsphere: fix l (langevin) " + force + thermostat, True),
            "fix addforce": (base + "fix a all addforce 1.0 0.0 0.0\nrun 1\n",
                             "fix hardsphere: fix a (addforce) " + force, True),
            "fix wall/gran": (WALLS + "fix w all wall/gran hooke 1000 NULL 0 NULL 0 0 zplane 0 NULL\nrun 1\n",
                              "fix hardsphere: fix w (wall/gran) " + wall, True),
            "fix wall/lj93": (WALLS + "fix w all wall/lj93 zlo EDGE 1.0 1.0 2.5\nrun 1\n",
                              "fix hardsphere: fix w (wall/lj93) " + wall, False),
            "fix wall/reflect": (WALLS + "fix w all wall/reflect zlo EDGE\nrun 1\n",
                                 "fix hardsphere: fix w (wall/reflect) " + wall, False),
            "fix setforce 1 NULL NULL": (base + "fix s all setforce 1.0 NULL NULL\nrun 1\n",
                                         "fix hardsphere: fix s (setforce) " + force +
                                         " ('setforce NULL NULL NULL', which sets nothing, is allowed)", False),
            "fix setforce v_f NULL NULL": (base + "variable f equal 0.0\nfix s all setforce v_f NULL NULL\nrun 1\n",
                                           "fix hardsphere: fix s (setforce) " + force, False),
            "fix spring": (base + "fix sp all spring tether 1.0 0 0 0 0.0\nrun 1\n",
                           "fix hardsphere: fix sp (spring) " + force, False),
            "fix spring/self": (base + "fix sp all spring/self 10.0\nrun 1\n",
                                "fix hardsphere: fix sp (spring/self) " + force, False),
            "fix efield": (base + "fix e all efield 1.0 0.0 0.0\nrun 1\n", "fix hardsphere: fix e (efield) " + force,
                           False),
            "fix aveforce": (base + "fix a all aveforce 1.0 0.0 0.0\nrun 1\n",
                             "fix hardsphere: fix a (aveforce) " + force, False),
            "fix recenter": (base + "fix r all recenter INIT INIT INIT\nrun 1\n",
                             "fix hardsphere: fix r (recenter) moves atoms inside the time step (initial_integrate)",
                             False),
            "fix ehex": (base + "fix e all ehex 1 0.5\nrun 1\n",
                         "fix hardsphere: fix e (ehex) corrects positions at the end of each step", True),
            "fix dt/reset": (base + "fix dt all dt/reset 1 NULL NULL 0.1\nrun 1\n",
                             "fix hardsphere: fix dt (dt/reset) changes the timestep during a run", False),
            # A fix that moves atoms at the end of a step is taken up, and its result checked.
            "fix moving atoms into overlaps": (base + python_mover(d, "x[:n] *= 0.5") + "run 20\n",
                                               "fix hardsphere: after fix p (python/invoke) at step 10: atom", True),
            # Messages that point at the real cause.
            "empty box": ("units lj\natom_style sphere\nregion b block 0 5 0 5 0 5\ncreate_box 1 b\n"
                          "pair_style hardsphere\npair_coeff * *\nfix hs all hardsphere\nrun 1\n",
                          "pair_style hardsphere: the box has no atoms", True),
            "empty box, pair_coeff with diameter": (
                "units lj\natom_style sphere\nregion b block 0 5 0 5 0 5\ncreate_box 1 b\npair_style hardsphere\n"
                "pair_coeff * * 1.0\nfix hs all hardsphere\nrun 1\n",
                "fix hardsphere: the box has no atoms; create or read them (create_atoms, read_data) before 'run'",
                False),
            "boundary m": (base.replace("boundary p p p", "boundary p p fm") + "run 1\n",
                           "fix hardsphere: boundary 'm' on z: shrink-wrapped faces move; use 'f' (fixed walls, "
                           "spheres bounce off them) or 'p'", True),
            "boundary s": (base.replace("boundary p p p", "boundary s p p") + "run 1\n",
                           "fix hardsphere: boundary 's' on x: shrink-wrapped faces move", False),
            "fix pour": (WALLS + region + "fix g all gravity 1.0 vector 0 0 -1\nfix p all pour 10 1 4767 region ins\n"
                         "run 1\n", "fix hardsphere: fix p (pour) " + inserts, True),
            "fix deposit": (WALLS + region + "fix dp all deposit 10 1 10 4767 region ins\nrun 1\n",
                            "fix hardsphere: fix dp (deposit) " + inserts, False),
            "fix evaporate": (WALLS + "fix e all evaporate 1 1 inner 1\nrun 1\n",
                              "fix hardsphere: fix e (evaporate) " + inserts, False),
            "minimize": (base + "minimize 0.0 0.0 10 10\n",
                         "fix hardsphere: hard spheres have no potential energy to minimise; use 'run'", True),
            # Big spheres need the serial path's own pass; the MPI path refuses them.
            "big sphere on the MPI path": (base.replace("fix hs all hardsphere\n", "fix hs all hardsphere path ghosts\n")
                                           + "set atom 1 diameter 3.0\nrun 1\n",
                                           "fix hardsphere: 1 atom(s) have a diameter above 2 x the median diameter 1 "
                                           "(largest 3): such big spheres run on one MPI rank only", True),
            "run_style respa": (base + "run_style respa 2 2\nrun 1\n",
                                "fix hardsphere: run_style respa is not supported", False),
        }
        for name, (script, phrase, mpi) in cases.items():
            if args.np > 1 and not mpi:
                continue
            rc, out = run_lmp(args, script, d, np_=args.np, expect_ok=False)
            err = [l for l in out.splitlines() if "ERROR" in l]
            ok &= check(rc != 0 and err and phrase in err[0], f"np={args.np}: {name}: {err[:1]}")
    return ok


def defaults(args):
    """An input without 'neigh_modify every 1 delay 0 check yes' runs: the fix sets those itself and
    says so once; the collisions are those with the explicit setting and the standalone stepper's.
    Allowed fixes (setforce NULL NULL NULL, momentum, balance) change nothing."""
    ok = True
    tag = f"np={args.np}: "
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "500", "--phi", "0.3", "--steps", "0", "--write-data", "init.data")
        ref = standalone(args, d, "--read-data", "init.data", "--steps", "200", "--dt", "0.01")
        explicit = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """
thermo_style custom step ke f_hs[1]
thermo 100
run 100
run 100
"""
        default = explicit.replace("neigh_modify every 1 delay 0 check yes\n", "")
        # Serial: LAMMPS checks its lists every step. The owned + ghost path (2 ranks) decides
        # re-neighbouring itself and says so whatever the settings were.
        note = ("fix hardsphere: neighbour lists set to 'neigh_modify every 1 delay 0 check yes'" if args.np == 1
                else "fix hardsphere: neighbour lists rebuilt only when the fix asks")
        counts = {}
        for name, script in (("explicit", explicit), ("default", default),
                             ("every 2 delay 4 check no", explicit.replace("every 1 delay 0 check yes",
                                                                          "every 2 delay 4 check no"))):
            rc, out = run_lmp(args, script, d, np_=args.np)
            rows = thermo(out)
            counts[name] = rows[-1]["f_hs[1]"]
            notes = [l for l in out.splitlines() if note in l]
            if name == "explicit" and args.np == 1:
                ok &= check(not notes, tag + "explicit neigh_modify every 1 delay 0 check yes: no note")
            elif name == "explicit":
                ok &= check(len(notes) == 1 and "(were 'every 1 delay 0 check yes')" in notes[0],
                            tag + f"explicit: one note over two runs: {notes}")
            else:
                was = "every 1 delay 10 check yes" if name == "default" else name
                ok &= check(len(notes) == 1 and f"(were '{was}')" in notes[0],
                            tag + f"{name}: one note over two runs: {notes}")
        ok &= check(counts["explicit"] == counts["default"] == counts["every 2 delay 4 check no"] == ref["collisions"],
                    tag + f"collisions explicit / default / every 2 delay 4 check no / standalone: "
                    f"{counts['explicit']:.0f} / {counts['default']:.0f} / {counts['every 2 delay 4 check no']:.0f} "
                    f"/ {ref['collisions']}")
        # With newton on (the default) the fix skips LAMMPS's reverse communication of ghost
        # forces during runs (hard spheres exert none), says so once, and restores the setting.
        newton = explicit.replace("thermo_style custom step ke f_hs[1]", "variable nw equal is_active(newton,any)\n"
                                  "thermo_style custom step ke f_hs[1] v_nw\nwrite_data pre.data\nprint \"before: newton ${nw}\"") + \
            'print "after: newton ${nw}"\nrun 50 pre no\nprint "after pre no: newton ${nw}"\n'
        rc, out = run_lmp(args, newton, d, np_=args.np)
        rows = thermo(out.split("after: newton")[0])  # the two runs with setup
        notes = [l for l in out.splitlines() if "ghost forces are not communicated back" in l]
        during = {r["v_nw"] for r in rows}
        ok &= check(len(notes) == 1 and during == {0} and "after: newton 1" in out and "before: newton 1" in out
                    and "after pre no: newton 1" in out and rows[-1]["f_hs[1]"] == ref["collisions"],
                    tag + f"newton on: off during the runs ({during}), one note ({len(notes)}), on before (write_data's init) and after, "
                    f"collisions {rows[-1]['f_hs[1]']:.0f} == standalone {ref['collisions']}")
        # Fixes that are allowed: setforce NULL NULL NULL (sets nothing), momentum (end of step;
        # the total momentum is zero already), balance (moves sub-domain boundaries only).
        allowed = default.replace("run 100\nrun 100\n", "") + """fix idle all setforce NULL NULL NULL
fix mom all momentum 50 linear 1 1 1
fix lb all balance 50 1.0 shift x 10 1.0
run 200
"""
        rc, out = run_lmp(args, allowed, d, np_=args.np)
        n = thermo(out)[-1]["f_hs[1]"]
        ok &= check(n == ref["collisions"], tag + f"setforce NULL NULL NULL + momentum + balance: collisions {n:.0f} == "
                    f"standalone {ref['collisions']}")
        # A mixture with per-atom diameters for type 1 ('pair_coeff 1 1') and 0.6 for type 2: the
        # 1-2 pair takes the per-atom diameters too (not a mix of the resolved 1 1 value), also
        # after write_restart/read_restart.
        mix = """units lj
atom_style sphere
boundary p p p
lattice fcc 0.5
region box block 0 4 0 4 0 4
create_box 2 box
create_atoms 1 box
set type 1 type/fraction 2 0.3 2934
set type 1 diameter 1.0
set type 2 diameter 0.6
set type 1 mass 1.0
set type 2 mass 0.216
velocity all create 1.0 3049 dist gaussian mom yes
pair_style hardsphere
pair_coeff 1 1
pair_coeff 2 2 0.6
neighbor 0.5 bin
timestep 0.005
fix hs all hardsphere
thermo_style custom step ke f_hs[1]
run 100
write_restart mix.restart
"""
        rc, out = run_lmp(args, mix, d, np_=args.np, expect_ok=False)
        rc2, out2 = run_lmp(args, "read_restart mix.restart\nfix hs all hardsphere\nthermo_style custom step ke "
                            "f_hs[1]\nrun 100\n", d, np_=args.np, expect_ok=False)
        good = rc == 0 and rc2 == 0 and thermo(out)[-1]["f_hs[1]"] > 0 and thermo(out2)[-1]["f_hs[1]"] > 0
        ok &= check(good, tag + "pair_coeff 1 1 (per-atom) + 2 2 0.6: runs, and again after read_restart" +
                    ("" if good else ": " + [l for l in (out + out2).splitlines() if "ERROR" in l][:1].__str__()))
    return ok


def outputs(args):
    """f_ID[9] (Z) and f_ID[10] (P) against the standalone run's compressibility_factor and
    pressure on the same state, dt and steps; P == N <T> Z / V; the temperature averaged over
    the steps when it changes (velocity between runs, a thermostat)."""
    ok = True
    tag = f"np={args.np}: "
    # Serial: the standalone stepper itself, so Z agrees to round-off. Two ranks: the same
    # collisions, the virial to round-off amplified by chaotic dynamics (see identical()).
    tol = 1e-12 if args.np == 1 else 1e-9
    with tempfile.TemporaryDirectory() as d:
        ref = gas_reference(args, d)
        script = pressure_run("step atoms vol ke f_hs[1] f_hs[9] f_hs[10]")
        rc, out = run_lmp(args, script, d, np_=args.np)
        last = thermo(out)[-1]
        n, vol = last["Atoms"], last["Volume"]
        t = 2.0 * last["KinEng"] / 3.0  # thermo ke is per atom in lj units; T = 2 KE / (3N)
        z, p = last["f_hs[9]"], last["f_hs[10]"]
        ok &= check(last["f_hs[1]"] == ref["collisions"], tag + f"collisions {last['f_hs[1]']:.0f} == {ref['collisions']}")
        ok &= check(abs(z / ref["compressibility_factor"] - 1) < tol,
                    tag + f"f_hs[9] Z {z!r} vs standalone {ref['compressibility_factor']!r} "
                    f"(rel {abs(z / ref['compressibility_factor'] - 1):.1e} < {tol:g})")
        ok &= check(abs(p / ref["pressure"] - 1) < tol,
                    tag + f"f_hs[10] P {p!r} vs standalone {ref['pressure']!r}")
        ok &= check(abs(p / (n * t * z / vol) - 1) < 1e-12, tag + f"f_hs[10] == N T Z / V = {n * t * z / vol!r}")
        # LAMMPS's own pressure, averaged over the run's steps, is the same time average.
        ok &= check(abs(p / last["f_pav"] - 1) < 1e-12, tag + f"f_hs[10] == <press> over the run {last['f_pav']!r}")

        # 'timing yes' prints, at the end of each run, wall time per part of the fix's step: the
        # parts of the run's path, within LAMMPS's loop time; the collisions stay the same.
        timed = script.replace("fix hs all hardsphere", "fix hs all hardsphere timing yes").replace(
            "thermo 200\nrun 200\n", "thermo 100\nrun 100\nrun 100\n").replace("ave/time 1 200 200", "ave/time 1 100 100")
        rc, out = run_lmp(args, timed, d, np_=args.np)
        lines = out.splitlines()
        heads = [k for k, l in enumerate(lines) if l.startswith("fix hardsphere timing over 100 steps")]
        loops = [float(l.split()[3]) for l in lines if l.startswith("Loop time of")]
        parts = []
        for k in heads:
            rows = {}
            for l in lines[k + 1:k + 10]:
                if not l.startswith("  "):
                    break
                *name, lo, avg, hi = l.split()
                rows[" ".join(name)] = (float(lo), float(avg), float(hi))
            parts.append(rows)
        path_rows = "owner check (incl. waiting for ranks)" if args.np > 1 else "writing LAMMPS's x and v"
        good = (len(heads) == 2 and len(loops) == 2 and all(
            r.get("steps (the stepper)", (0, 0, 0))[1] > 0 and path_rows in r and
            all(lo <= avg <= hi for lo, avg, hi in r.values()) and sum(v[2] for v in r.values()) <= 1.05 * loop
            for r, loop in zip(parts, loops)) and thermo(out)[-1]["f_hs[1]"] == ref["collisions"])
        ok &= check(good, tag + f"timing yes: one table per run, parts within the loop time {loops}: "
                    f"{[{k: v[1] for k, v in r.items()} for r in parts]}")
        rc, out = run_lmp(args, script.replace("fix hs all hardsphere", "fix hs all hardsphere timing maybe"), d,
                          np_=args.np, expect_ok=False)
        ok &= check(rc != 0 and "timing must be 'yes' or 'no', got 'maybe'" in out, tag + "timing maybe is refused")

        # compute stress/atom holds each atom's half of its collisions' virial in the step (as
        # press holds the step's total): summed, it is LAMMPS's press at every thermo step
        # (including the first of a second run), through atom sorting every 7 steps and, on 2
        # ranks, atoms changing ranks; per atom, 2 ranks give the serial values.
        script = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """atom_modify sort 7 1.0
compute sa all stress/atom NULL
compute ss all reduce sum c_sa[1] c_sa[2] c_sa[3]
variable pa equal -(c_ss[1]+c_ss[2]+c_ss[3])/(3*vol)
thermo_style custom step press v_pa f_hs[1]
thermo_modify format float %.17g
thermo 10
dump sd all custom 200 stress.dump id c_sa[1] c_sa[2] c_sa[3] c_sa[4] c_sa[5] c_sa[6]
dump_modify sd sort id format float %.17g
run 200
undump sd
run 20
"""
        stress = {}
        for np_ in sorted({1, args.np}):
            rc, out = run_lmp(args, script, d, np_=np_)
            rows = [r for b in thermo_blocks(out) for r in b]
            worst = max(abs(r["Press"] - r["v_pa"]) / abs(r["Press"]) for r in rows)
            lines = open(os.path.join(d, "stress.dump")).read().splitlines()
            start = max(k for k, ln in enumerate(lines) if ln.startswith("ITEM: ATOMS")) + 1  # step 200
            stress[np_] = np.array([[float(t) for t in ln.split()[1:]] for ln in lines[start:]])
            mean_press = sum(r["Press"] for r in rows) / len(rows)
            ok &= check(len(rows) == 24 and worst < 1e-10 and mean_press > 2.0,
                        f"np={np_}: compute stress/atom summed == press at every thermo step (rel {worst:.1e}, "
                        f"{len(rows)} rows, <press> {mean_press:.3f}: the collisions' part is in)")
        if args.np > 1:
            diff = np.abs(stress[args.np] - stress[1]).max() / np.abs(stress[1]).max()
            ok &= check(stress[1].shape == stress[args.np].shape and diff < 1e-6,
                        tag + f"compute stress/atom per atom at step 200 equals the serial run's (rel {diff:.1e})")

        # Walls (boundary p p f): V is the box volume, as in the standalone (which reports the
        # wall pressures separately).
        run_lmp(args, WALLS.split("pair_style")[0] + "write_data walls.data\n", d)
        ref = standalone(args, d, "--read-data", "walls.data", "--boundary", "p,p,w", "--steps", "200", "--dt", "0.01")
        script = HEADER.format(data="walls.data", skin=0.5, dt=0.01).replace("boundary p p p", "boundary p p f") + """
thermo_style custom step atoms vol ke f_hs[1] f_hs[5] f_hs[9] f_hs[10]
thermo_modify format float %.17g
thermo 200
run 200
"""
        rc, out = run_lmp(args, script, d, np_=args.np)
        last = thermo(out)[-1]
        z, p = last["f_hs[9]"], last["f_hs[10]"]
        n, vol, t = last["Atoms"], last["Volume"], 2.0 * last["KinEng"] / 3.0
        ok &= check(last["f_hs[1]"] == ref["collisions"] and last["f_hs[5]"] == ref["wall_collisions"],
                    tag + f"walls: collisions {last['f_hs[1]']:.0f} == {ref['collisions']}, "
                    f"bounces {last['f_hs[5]']:.0f} == {ref['wall_collisions']}")
        ok &= check(abs(z / ref["compressibility_factor"] - 1) < tol and abs(p / ref["pressure"] - 1) < tol
                    and abs(p / (n * t * z / vol) - 1) < 1e-12,
                    tag + f"walls: Z {z!r} vs {ref['compressibility_factor']!r}, P {p!r} vs {ref['pressure']!r} "
                    f"== N T Z / V with V = box volume {vol:g}")

        # The temperature in Z is averaged over the steps: a velocity change between runs and a
        # thermostat acting every step (temp/berendsen) both enter with their duration.
        script = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """
thermo_style custom step atoms ke f_hs[3] f_hs[4] f_hs[9] f_hs[10]
thermo_modify format float %.17g
thermo 1
run 100
velocity all scale 1.5
run 50
fix tb all temp/berendsen 1.0 1.0 0.1
run 50
"""
        rc, out = run_lmp(args, script, d, np_=args.np)
        rows = {}
        for line in out.splitlines():  # every step's row once (each run repeats its first step)
            s = line.split()
            if len(s) == 7 and s[0].isdigit():
                try:
                    rows[int(s[0])] = [float(v) for v in s]
                except ValueError:
                    pass
        # Step k of the fix uses the temperature at the end of step k - 1, after end_of_step fixes
        # and, at a run's first step, after the commands between runs (each run's first row,
        # which repeats the previous run's last step, comes later in the log and is kept).
        temps = [2.0 * rows[k][2] / 3.0 for k in range(200)]
        last = rows[200]
        n, w, tt, z, p = last[1], last[3], last[4], last[5], last[6]
        t_mean = sum(temps) * 0.01 / tt
        z_expect = 1.0 + w / (3.0 * n * t_mean * tt)
        ok &= check(abs(z / z_expect - 1) < 1e-10 and abs(t_mean / temps[0] - 1) > 0.05,
                    tag + f"T over the steps ({temps[0]:.4f} -> {temps[120]:.4f} -> {temps[-1]:.4f}, mean "
                    f"{t_mean:.6f}): f_hs[9] {z!r} == 1 + W / (3 N <T> t) = {z_expect!r}")
    return ok


def runs(args):
    """run N split into pieces, write_restart/read_restart (in a second lmp_hs: `clear`
    recreates LAMMPS's style maps, dropping styles registered at start-up) and thermo every step
    keep working: the collisions are those of one straight run."""
    ok = True
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "500", "--phi", "0.3", "--steps", "0", "--write-data", "init.data")
        ref = standalone(args, d, "--read-data", "init.data", "--steps", "150", "--dt", "0.01")
        script = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """
thermo_style custom step ke press f_hs[1]
thermo_modify format float %.17g
thermo 1
run 50
run 50
write_restart r.restart
"""
        rc, out1 = run_lmp(args, script, d, np_=args.np)
        script = """read_restart r.restart
neigh_modify every 1 delay 0 check yes
fix hs all hardsphere
thermo_style custom step ke f_hs[1]
thermo_modify format float %.17g
run 50
"""
        rc, out2 = run_lmp(args, script, d, np_=args.np)
        # velocity and displace_atoms between runs: the fix picks up the new state.
        script = """read_restart r.restart
neigh_modify every 1 delay 0 check yes
fix hs all hardsphere
velocity all scale 1.2
displace_atoms all move 0.1 0.2 0.3
thermo_style custom step temp ke f_hs[1]
thermo_modify format float %.17g
run 100
"""
        rc, out3 = run_lmp(args, script, d, np_=args.np)
        r3 = thermo(out3)
        ok &= check(r3[-1]["f_hs[1]"] > 0 and abs(r3[-1]["KinEng"] / r3[0]["KinEng"] - 1) < 1e-12
                    and abs(r3[0]["Temp"] - 1.2) < 1e-12,
                    f"np={args.np}: velocity scale (T = 1.2) + displace_atoms between runs: T {r3[0]['Temp']:.12f}, "
                    f"{r3[-1]['f_hs[1]']:.0f} collisions, energy kept")
        # Another fix changing velocities during a run (a Berendsen thermostat to T = 2): the
        # hard-sphere step takes them up, the gas heats, energy changes only by the rescaling.
        script = """read_restart r.restart
neigh_modify every 1 delay 0 check yes
fix hs all hardsphere
fix tb all temp/berendsen 2.0 2.0 0.05
thermo_style custom step temp f_hs[1]
thermo 300
run 300
"""
        rc, out4 = run_lmp(args, script, d, np_=args.np)
        r4 = thermo(out4)
        ok &= check(abs(r4[-1]["Temp"] - 2.0) < 0.05 and r4[-1]["f_hs[1]"] > 1000,
                    f"np={args.np}: fix temp/berendsen during the run: T {r4[0]['Temp']:.3f} -> {r4[-1]['Temp']:.3f} "
                    f"(target 2), {r4[-1]['f_hs[1]']:.0f} collisions")
        # Unwrapped coordinates stay continuous: on one rank the fix writes LAMMPS's copy only on
        # output steps (here every 20), with image flags from its own wrap counts, through
        # LAMMPS's periodic wraps and atom sorts (every 7 steps here). A wrong image shows as a
        # jump of a box length; 20 steps move an atom by ~0.3 at most.
        script = """read_restart r.restart
neigh_modify every 1 delay 0 check yes
atom_modify sort 7 1.0
fix hs all hardsphere
dump tr all custom 20 traj.dump id xu yu zu
dump_modify tr sort id format float %.17g
run 400
"""
        run_lmp(args, script, d, np_=args.np)
        frames = []
        with open(os.path.join(d, "traj.dump")) as f:
            lines = f.read().splitlines()
        for k, line in enumerate(lines):
            if line.startswith("ITEM: ATOMS"):
                n_at = int(lines[k - 5])
                frames.append(np.array([[float(t) for t in ln.split()] for ln in lines[k + 1:k + 1 + n_at]]))
        box, _, _ = read_data(os.path.join(d, "init.data"))
        jump = np.abs(np.diff(np.array([f[:, 1:4] for f in frames]), axis=0)).max()
        ok &= check(len(frames) == 21 and jump < box.min() / 4,
                    f"np={args.np}: unwrapped coordinates continuous over 400 steps with sorting: largest move "
                    f"in 20 steps {jump:.3f} < L/4 = {box.min() / 4:.3f}")
        # Far travel between writes: 64 spheres in a box of ~4.4 diameters, 2000 steps with x
        # written every step (dump every step) or only at the start and the end (dump every
        # 2000, thermo at the end only): the unwrapped positions at the end must agree.
        standalone(args, d, "--n", "64", "--phi", "0.3", "--steps", "0", "--write-data", "small.data")
        ends = []
        for every in (1, 2000):
            script = HEADER.format(data="small.data", skin=0.5, dt=0.01) + f"""
dump tr all custom {every} far{every}.dump id xu yu zu
dump_modify tr sort id format float %.17g
thermo 0
run 2000
"""
            run_lmp(args, script, d, np_=args.np)
            lines = open(os.path.join(d, f"far{every}.dump")).read().splitlines()
            ends.append(np.array([[float(t) for t in ln.split()[1:4]] for ln in lines[-64:]]))
        box_s, x0_s, _ = read_data(os.path.join(d, "small.data"))
        travel = np.abs(ends[0] - x0_s).max()
        ok &= check(np.abs(ends[0] - ends[1]).max() < 1e-9 and travel > box_s.min(),
                    f"np={args.np}: unwrapped positions after 2000 steps written every step vs only at the end: "
                    f"max difference {np.abs(ends[0] - ends[1]).max():.1e} (atoms travelled up to {travel:.1f}, box "
                    f"{box_s.min():.1f})")
        # A fix acting only every 10 steps (temp/rescale at end_of_step): in serial the state
        # is written for it on those steps and the rescaled velocities are taken up after.
        script = """read_restart r.restart
neigh_modify every 1 delay 0 check yes
fix hs all hardsphere
fix tr all temp/rescale 10 0.5 0.5 0.0 1.0
thermo_style custom step temp f_hs[1]
thermo_modify format float %.17g
thermo 25
run 200
"""
        rc, out5 = run_lmp(args, script, d, np_=args.np)
        r5 = thermo(out5)
        t5 = [r["Temp"] for r in r5[1:]]  # steps 125 ... 300: the first rescale is at step 110
        ok &= check(len(t5) == 8 and max(abs(t - 0.5) for t in t5) < 1e-12 and r5[-1]["f_hs[1]"] > 500,
                    f"np={args.np}: fix temp/rescale every 10 steps: T {r5[0]['Temp']:.3f} -> "
                    f"{min(t5):.15f}..{max(t5):.15f} at every thermo step after (target 0.5, elastic steps keep it)")
        # A fix that moves atoms at the end of a step (python/invoke, not known to leave positions
        # alone): LAMMPS's x is compared after it, and moved atoms are taken up. Shifting every atom
        # is a symmetry of the periodic gas: the centre of mass moves by 10 x 0.05 more than
        # without the shift, and the collisions are those of the run without it.
        com = {}
        for mover in ("", python_mover(d, "x[:n, 0] += 0.05")):
            script = """read_restart r.restart
neigh_modify every 1 delay 0 check yes
fix hs all hardsphere
{}compute cm all com
thermo_style custom step ke f_hs[1] f_hs[6] c_cm[1]
thermo_modify format float %.17g
thermo 100
run 100
""".format(mover)
            rc, out = run_lmp(args, script, d, np_=args.np)
            com[bool(mover)] = thermo(out)
        plain, moved = com[False], com[True]
        extra = (moved[-1]["c_cm[1]"] - moved[0]["c_cm[1]"]) - (plain[-1]["c_cm[1]"] - plain[0]["c_cm[1]"])
        ok &= check(abs(extra - 0.5) < 1e-9 and moved[-1]["f_hs[1]"] == plain[-1]["f_hs[1]"] > 0
                    and abs(moved[-1]["KinEng"] / moved[0]["KinEng"] - 1) < 1e-12 and moved[-1]["f_hs[6]"] == 0,
                    f"np={args.np}: fix python/invoke shifting every atom by 0.05 every 10 steps: centre of mass "
                    f"{extra:.12f} further (10 x 0.05), {moved[-1]['f_hs[1]']:.0f} collisions == "
                    f"{plain[-1]['f_hs[1]']:.0f} without it, energy kept")
        # 'run N pre no every M COMMAND' skips the fix's setup between the pieces: commands that
        # change velocities, delete or move atoms still take effect (the serial path re-reads the
        # atoms; on several ranks LAMMPS's ghosts are taken up again, or one step runs for all
        # atoms while LAMMPS re-neighbours), and no ghost copy disagrees with its owner after.
        for command, expect in (("print piece", "nothing changed"), ("velocity all scale 2.0", "T 2"),
                                ("delete_atoms region corner", "fewer atoms"),
                                ("displace_atoms all move 0.3 0.1 0 units box", "atoms moved"),
                                ("timestep 0.005", "dt 0.005")):
            script = """read_restart r.restart
fix hs all hardsphere
region corner block 0 2 0 2 0 2
thermo_style custom step atoms temp ke f_hs[1] f_hs[6] f_hs[4]
thermo_modify format float %.17g
thermo 50
run 100 pre no every 50 "{}"
""".format(command)
            rc, out6 = run_lmp(args, script, d, np_=args.np)
            r6 = thermo(out6)  # the second piece: steps 50 .. 100
            good = abs(r6[-1]["KinEng"] / r6[0]["KinEng"] - 1) < 1e-12 and r6[-1]["f_hs[6]"] == 0
            if expect == "T 2":
                good &= abs(r6[0]["Temp"] - 2.0) < 1e-12
            elif expect == "fewer atoms":
                good &= r6[0]["Atoms"] < 500
            elif expect == "dt 0.005":  # 50 steps of 0.01, then 50 of 0.005
                good &= abs(r6[-1]["f_hs[4]"] - 0.75) < 1e-12
            ok &= check(good and r6[-1]["f_hs[1]"] > r6[0]["f_hs[1]"],
                        f"np={args.np}: run pre no every 50 \"{command}\": {r6[0]['Atoms']:.0f} atoms, T "
                        f"{r6[0]['Temp']:.12f}, energy kept over the second piece, steps re-run "
                        f"{r6[-1]['f_hs[6]']:.0f} ({expect})")
        # All atoms in the middle of one half of a long box (x 6..14 of 40): on 2 ranks the
        # other sub-domain and its ghost shell start empty (that rank has no stepper but must
        # join every step's collective calls) and fill up during the run. The collisions are
        # the standalone stepper's.
        script = """units lj
atom_style sphere
boundary p p p
lattice sc 0.125
region box block 0 20 0 5 0 5
create_box 1 box
region half block 2.5 7.5 0 5 0 5
create_atoms 1 region half
set type 1 mass 1.0
velocity all create 1.0 4928 dist gaussian mom yes
write_data half.data
"""
        run_lmp(args, script, d)
        ref_half = standalone(args, d, "--read-data", "half.data", "--steps", "400", "--dt", "0.01")
        script = HEADER.format(data="half.data", skin=0.5, dt=0.01) + """
thermo_style custom step ke f_hs[1]
thermo_modify format float %.17g
thermo 400
run 400
"""
        rc, out7 = run_lmp(args, script, d, np_=args.np)
        r7 = thermo(out7)
        ok &= check(r7[-1]["f_hs[1]"] == ref_half["collisions"] and abs(r7[-1]["KinEng"] / r7[0]["KinEng"] - 1) < 1e-12,
                    f"np={args.np}: atoms in one half of the box (the other rank starts without atoms): "
                    f"{r7[-1]['f_hs[1]']:.0f} collisions == standalone {ref_half['collisions']}, energy kept")
        # rerun reads snapshots and integrates nothing: a snapshot is not checked for overlaps
        # (dumps round positions), its pressure has no collision part, the collisions stay as they
        # were, and pair_style hardsphere works there without the fix.
        script = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """run 20
write_dump all custom snap.dump id x y z modify format float %.17g
"""
        run_lmp(args, script, d, np_=args.np)
        with open(os.path.join(d, "snap.dump")) as f:
            lines = f.read().splitlines()
        rows = {int(l.split()[0]): i for i, l in enumerate(lines) if i > lines.index("ITEM: ATOMS id x y z")}
        x2 = [float(t) for t in lines[rows[2]].split()[1:]]
        lines[rows[1]] = f"1 {x2[0] + 0.5!r} {x2[1]!r} {x2[2]!r}"  # atom 1 overlaps atom 2
        with open(os.path.join(d, "snap.dump"), "w") as f:
            f.write("\n".join(lines) + "\n")
        script = HEADER.format(data="init.data", skin=0.5, dt=0.01) + """compute pk all pressure thermo_temp ke
thermo_style custom step press c_pk f_hs[1]
thermo_modify format float %.17g
run 20
rerun snap.dump dump x y z
unfix hs
thermo_style custom step press c_pk
rerun snap.dump dump x y z
"""
        rc, out8 = run_lmp(args, script, d, np_=args.np, expect_ok=False)
        b8 = thermo_blocks(out8)
        good = rc == 0 and len(b8) == 3 and all(len(b) == 1 for b in b8[1:])
        if good:
            fixed, alone = b8[1][0], b8[2][0]
            good = (fixed["f_hs[1]"] == b8[0][-1]["f_hs[1]"] and abs(fixed["Press"] / fixed["c_pk"] - 1) < 1e-12
                    and abs(alone["Press"] / alone["c_pk"] - 1) < 1e-12)
        ok &= check(good, f"np={args.np}: rerun of an overlapping snapshot with and without the fix: "
                          f"{[b[-1] for b in b8] if rc == 0 else out8[-400:]}")
        blocks, cur = [], None
        for line in (out1 + out2).splitlines():
            s = line.split()
            if s and s[0] == "Step":
                cur = []
                blocks.append(cur)
            elif cur is not None and s and s[0] == "Loop":
                cur = None
            elif cur is not None and len(s) >= 3:
                cur.append([float(t) for t in s])
        tag = f"np={args.np}: "
        ok &= check(len(blocks) == 3 and len(blocks[0]) == 51, tag + "three runs, thermo every step")
        total = blocks[1][-1][3] + blocks[2][-1][2]
        ok &= check(total == ref["collisions"], tag + f"collisions over 50 + 50 + restart + 50: {total:.0f} == standalone {ref['collisions']}")
        ok &= check(abs(blocks[2][-1][1] / blocks[0][0][1] - 1) < 1e-12, tag + "energy kept across runs and the restart")
    return ok


def pressure_follows_temperature(tag, last):
    """Where the temperature changes inside the steps (inelastic collisions, gravity), P
    (f_hs[10]) averages the temperature at every step's end: LAMMPS's press averaged over the
    run's steps (f_pav) is the same sum."""
    p, pav = last["f_hs[10]"], last["f_pav"]
    return check(abs(p / pav - 1) < 1e-12, tag + f"P {p!r} == LAMMPS's <press> {pav!r}")


def restitution(args):
    """`fix hardsphere restitution e` is the standalone's --restitution: in serial the same
    collisions and kinetic energy to round-off; on 2 ranks statistically equal (the runs part by
    rounding, and the TC model's collision history restarts when LAMMPS re-neighbours). A bad
    value is refused with its text."""
    ok = True
    tag = f"np={args.np}: "
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "2000", "--phi", "0.1", "--steps", "0", "--write-data", "init.data")
        ref = standalone(args, d, "--read-data", "init.data", "--steps", "300", "--dt", "0.02", "--restitution", "0.8")
        script = HEADER.format(data="init.data", skin=0.5, dt=0.02).replace(
            "fix hs all hardsphere", "fix hs all hardsphere restitution 0.8") + """
compute p all pressure thermo_temp
fix pav all ave/time 1 300 300 c_p
thermo_style custom step ke f_hs[1] f_hs[10] f_pav
thermo_modify format float %.17g
thermo 300
run 300
"""
        rc, out = run_lmp(args, script, d, np_=args.np)
        rows = thermo(out)
        n_atoms = 2000
        ke0, ke1, coll = rows[0]["KinEng"] * n_atoms, rows[-1]["KinEng"] * n_atoms, rows[-1]["f_hs[1]"]
        ok &= check(abs(ke0 - ref["kinetic_energy_initial"]) < 1e-9 * ke0, tag + "same start")
        if args.np == 1:
            ok &= check(coll == ref["collisions"] and abs(ke1 / ref["kinetic_energy_final"] - 1) < 1e-12,
                        tag + f"collisions {coll:.0f} == standalone {ref['collisions']}, kinetic energy "
                        f"{ke1:.12g} vs {ref['kinetic_energy_final']:.12g}")
        else:
            ok &= check(abs(coll / ref["collisions"] - 1) < 0.01 and abs(ke1 / ref["kinetic_energy_final"] - 1) < 0.01,
                        tag + f"collisions {coll:.0f} vs standalone {ref['collisions']}, kinetic energy {ke1:.6g} vs "
                        f"{ref['kinetic_energy_final']:.6g} (within 1%)")
        ok &= check(ke1 < 0.6 * ke0, tag + f"the gas cooled: {ke0:.6g} -> {ke1:.6g}")
        ok &= pressure_follows_temperature(tag, rows[-1])
        rc, out = run_lmp(args, script.replace("restitution 0.8", "restitution 1.5"), d, np_=args.np, expect_ok=False)
        ok &= check(rc != 0 and "fix hardsphere: restitution 1.5 must be in (0, 1]" in out, tag + "restitution 1.5 refused")
    return ok


def gravity(args):
    """`fix gravity` acts on the hard spheres through the stepper's parabolic flights: in serial
    the standalone's --gravity collision for collision, on 2 ranks statistically equal; kinetic +
    potential energy kept; a varying gravity is refused."""
    ok = True
    tag = f"np={args.np}: "
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "500", "--box", "10,10,40", "--boundary", "p,p,w", "--steps", "0",
                   "--write-data", "bed.data")
        ref = standalone(args, d, "--read-data", "bed.data", "--boundary", "p,p,w", "--gravity", "0,0,-1",
                         "--steps", "1000", "--dt", "0.005")
        script = HEADER.format(data="bed.data", skin=0.5, dt=0.005).replace("boundary p p p", "boundary p p f") + """
fix g all gravity 1.0 vector 0 0 -1
fix_modify g energy yes
compute p all pressure thermo_temp
fix pav all ave/time 1 1000 1000 c_p
thermo_style custom step ke pe f_hs[1] f_hs[5] f_hs[10] f_pav
thermo_modify format float %.17g
thermo 1000
run 1000
"""
        rc, out = run_lmp(args, script, d, np_=args.np)
        rows = thermo(out)
        ok &= pressure_follows_temperature(tag, rows[-1])
        n = 500
        coll, ke1 = rows[-1]["f_hs[1]"], rows[-1]["KinEng"] * n
        e0, e1 = (rows[0]["KinEng"] + rows[0]["PotEng"]) * n, (rows[-1]["KinEng"] + rows[-1]["PotEng"]) * n
        if args.np == 1:
            ok &= check(coll == ref["collisions"] and rows[-1]["f_hs[5]"] == ref["wall_collisions"] and
                        abs(ke1 / ref["kinetic_energy_final"] - 1) < 1e-12,
                        tag + f"collisions {coll:.0f} == {ref['collisions']}, bounces {rows[-1]['f_hs[5]']:.0f} == "
                        f"{ref['wall_collisions']}, kinetic energy {ke1:.12g} vs {ref['kinetic_energy_final']:.12g}")
        else:
            ok &= check(abs(coll / ref["collisions"] - 1) < 0.01 and abs(ke1 / ref["kinetic_energy_final"] - 1) < 0.01,
                        tag + f"collisions {coll:.0f} vs {ref['collisions']}, kinetic energy {ke1:.6g} vs "
                        f"{ref['kinetic_energy_final']:.6g} (within 1%)")
        ok &= check(ke1 > 5 * rows[0]["KinEng"] * n, tag + f"the spheres fell: kinetic energy x{ke1 / (rows[0]['KinEng'] * n):.1f}")
        # pe includes fix gravity's energy (fix_modify energy yes), measured from z = 0 like the standalone's.
        ok &= check(abs(e1 / e0 - 1) < 1e-9, tag + f"kinetic + potential energy kept: {e0:.12g} -> {e1:.12g}")
        varying = script.replace("fix g all gravity 1.0 vector 0 0 -1",
                                 "variable m equal 1.0+0.001*step\nfix g all gravity v_m vector 0 0 -1")
        rc, out = run_lmp(args, varying, d, np_=args.np, expect_ok=False)
        ok &= check(rc != 0 and "fix g (gravity) has a variable magnitude or direction" in out,
                    tag + "a varying gravity is refused")
    return ok


# LAMMPS's conversion factors (update.cpp): kinetic energy m v^2 -> energy (mvv2e) and
# N k T / V -> pressure (nktv2p); a force per mass as an acceleration is times 1 / mvv2e.
UNITS = {"real": (48.88821291 * 48.88821291, 68568.415), "metal": (1.0364269e-4, 1.6021765e6)}


def units(args):
    """Unit styles other than lj: the dynamics use x, v, dt and masses as they are, so the same
    numbers give the same collisions; Z is a ratio and stays; P (f_ID[10]) and the virial the fix
    hands LAMMPS come in the style's pressure and energy units, so f_ID[10] equals LAMMPS's own
    press averaged over the run; fix gravity's force per mass becomes the acceleration LAMMPS's
    integrators would give (kinetic + potential energy kept)."""
    ok = True
    tag = f"np={args.np}: "
    tol = 1e-12 if args.np == 1 else 1e-9
    with tempfile.TemporaryDirectory() as d:
        ref = gas_reference(args, d)
        standalone(args, d, "--n", "500", "--box", "10,10,40", "--boundary", "p,p,w", "--steps", "0",
                   "--write-data", "bed.data")
        ref_g = standalone(args, d, "--read-data", "bed.data", "--boundary", "p,p,w", "--gravity", "0,0,-1",
                           "--steps", "1000", "--dt", "0.005")
        for style, (mvv2e, nktv2p) in UNITS.items():
            rc, out = run_lmp(args, pressure_run("step f_hs[1] f_hs[9] f_hs[10]", style), d, np_=args.np)
            last = thermo(out)[-1]
            z, p = last["f_hs[9]"], last["f_hs[10]"]
            p_ref = ref["pressure"] * mvv2e * nktv2p
            ok &= check(last["f_hs[1]"] == ref["collisions"] and abs(z / ref["compressibility_factor"] - 1) < tol and
                        abs(p / p_ref - 1) < tol and abs(p / last["f_pav"] - 1) < 1e-12,
                        tag + f"units {style}: collisions {last['f_hs[1]']:.0f} == {ref['collisions']}, Z {z!r} vs "
                        f"{ref['compressibility_factor']!r}, P {p!r} vs the standalone's x mvv2e x nktv2p {p_ref!r} "
                        f"and LAMMPS's <press> {last['f_pav']!r}")
            # A force per mass of mvv2e is an acceleration of 1: the standalone's --gravity 0,0,-1.
            script = HEADER.format(data="bed.data", skin=0.5, dt=0.005).replace("units lj", f"units {style}").replace(
                "boundary p p p", "boundary p p f") + f"""
fix g all gravity {mvv2e!r} vector 0 0 -1
fix_modify g energy yes
thermo_style custom step ke pe f_hs[1]
thermo_modify format float %.17g
thermo 1000
run 1000
"""
            rc, out = run_lmp(args, script, d, np_=args.np)
            rows = thermo(out)
            e0, e1 = rows[0]["KinEng"] + rows[0]["PotEng"], rows[-1]["KinEng"] + rows[-1]["PotEng"]
            coll = rows[-1]["f_hs[1]"]
            same = coll == ref_g["collisions"] if args.np == 1 else abs(coll / ref_g["collisions"] - 1) < 0.01
            ok &= check(same and abs(e1 / e0 - 1) < 1e-9 and rows[-1]["KinEng"] > 5 * rows[0]["KinEng"],
                        tag + f"units {style}, fix gravity {mvv2e:g}: collisions {coll:.0f} vs standalone "
                        f"{ref_g['collisions']} ({'equal' if args.np == 1 else 'within 1%'}), kinetic + potential "
                        f"energy {e0:.12g} -> {e1:.12g}, kinetic x{rows[-1]['KinEng'] / rows[0]['KinEng']:.1f}")
        # No length or time scale is built in: the gas scaled to millimetre spheres (SI granular
        # work), to nanometres and up by 10^6, with the time step scaled alike, collides as the
        # unscaled one.
        length = read_data(os.path.join(d, "init.data"))[0][0]
        for scale in (1e-3, 1e-9, 1e6):
            script = HEADER.format(data="init.data", skin=0.5 * scale, dt=0.01 * scale).replace(
                "fix hs all hardsphere\n", "") + f"""
change_box all x final 0 {length * scale!r} y final 0 {length * scale!r} z final 0 {length * scale!r} remap units box
set group all diameter {scale!r}
set group all mass 1.0
fix hs all hardsphere
thermo_style custom step f_hs[1] f_hs[9]
thermo_modify format float %.17g
thermo 200
run 200
"""
            rc, out = run_lmp(args, script, d, np_=args.np)
            last = thermo(out)[-1]
            z = last["f_hs[9]"]
            # Scaled positions round differently: Z to 1e-9, the collisions exactly.
            ok &= check(last["f_hs[1]"] == ref["collisions"] and abs(z / ref["compressibility_factor"] - 1) < 1e-9,
                        tag + f"lengths and time step x {scale:g}: collisions {last['f_hs[1]']:.0f} == "
                        f"{ref['collisions']}, Z {z!r} vs {ref['compressibility_factor']!r}")
    return ok


def decompositions(args):
    """The owned + ghost path on LAMMPS's other decompositions: slabs thinner than the ghost
    shell (LAMMPS relays ghosts through two swaps), 2-d and 3-d grids (corner ghosts come via a
    neighbour's neighbour), tiled sub-domains from recursive bisection (static, and re-cut during
    the run), walls on a split axis, two sphere sizes. Every grid must give the
    standalone stepper's collisions and final state, keep the energy, and need no step re-run for
    all atoms: a relay that carried a wrong owner velocity would show up as re-runs. Ranks may
    exceed the cores (oversubscribed); 1000 spheres keep each run under a second."""
    ok = True
    # "rcb N": comm_style tiled, sub-domains cut by recursive bisection (balance rcb) on N ranks,
    # again every 20 steps on the walls scene (fix balance).
    grids = {"periodic": ["2 1 1", "3 1 1", "4 1 1", "2 2 1", "1 2 2", "2 2 2", "3 2 1", "rcb 3", "rcb 4"],
             "walls": ["1 1 2", "1 1 4", "2 2 2", "rcb 3"], "two sizes": ["2 1 1", "3 1 1", "2 2 2"]}
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "1000", "--phi", "0.3", "--steps", "0", "--write-data", "periodic.data")
        standalone(args, d, "--n", "1000", "--phi", "0.3", "--boundary", "p,p,w", "--steps", "0", "--write-data",
                   "walls.data")
        # Every third sphere shrunk to diameter 0.6 (at the same density, so lighter): no overlaps.
        with open(os.path.join(d, "periodic.data")) as f, open(os.path.join(d, "two_sizes.data"), "w") as g:
            section = None
            for line in f:
                s = line.split()
                if s and s[0] in ("Atoms", "Velocities"):
                    section = s[0]
                elif section == "Atoms" and len(s) >= 7 and int(s[0]) % 3 == 0:
                    s[2] = "0.6"
                    line = " ".join(s) + "\n"
                g.write(line)
        for scene, scene_grids in grids.items():
            data, walls = scene.replace(" ", "_") + ".data", scene == "walls"
            opts = ["--boundary", "p,p,w"] if walls else []
            # Positions differ from the standalone's by round-off that chaos grows ~100-fold per 50
            # steps, faster with the light small spheres: they run 100 steps, the others 200.
            steps = 100 if scene == "two sizes" else 200
            ref = standalone(args, d, "--read-data", data, *opts, "--steps", str(steps), "--dt", "0.01", "--write-data",
                             "sa.data")
            for grid in scene_grids:
                rcb = grid.startswith("rcb")
                ranks = int(grid.split()[1]) if rcb else int(np.prod([int(t) for t in grid.split()]))
                layout = "comm_style tiled" if rcb else f"processors {grid}"
                script = HEADER.format(data=data, skin=0.5, dt=0.01).replace("read_data", f"{layout}\nread_data")
                if rcb:
                    balance = "fix bal all balance 20 1.0 rcb" if walls else "balance 1.0 rcb"
                    script = script.replace("fix hs all hardsphere", f"fix hs all hardsphere\n{balance}")
                script += """
thermo_style custom step ke f_hs[1] f_hs[5] f_hs[6]
thermo_modify format float %.17g
thermo {steps}
run {steps}
write_data lmp.data
""".format(steps=steps)
                if walls:
                    script = script.replace("boundary p p p", "boundary p p f")
                rc, out = run_lmp(args, script, d, np_=ranks)
                first, last = thermo(out)[0], thermo(out)[-1]
                dx, dv = state_difference(os.path.join(d, "sa.data"), os.path.join(d, "lmp.data"),
                                          (True, True, not walls))
                ok &= check(last["f_hs[1]"] == ref["collisions"] and last["f_hs[5]"] == ref["wall_collisions"] and
                            last["f_hs[6]"] == 0 and abs(last["KinEng"] / first["KinEng"] - 1) < 1e-12 and
                            dx < 1e-6 and dv < 1e-6,
                            f"{scene}, {'balance' if rcb else 'processors'} {grid} ({ranks} ranks): collisions {last['f_hs[1]']:.0f} == "
                            f"standalone {ref['collisions']}, wall bounces {last['f_hs[5]']:.0f} == "
                            f"{ref['wall_collisions']}, steps re-run {last['f_hs[6]']:.0f}, energy "
                            f"{first['KinEng']:.17g} -> {last['KinEng']:.17g}, max |dx| {dx:.1e}, |dv| {dv:.1e}")
    return ok


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("check", choices=["identical", "conservation", "errors", "runs", "defaults", "outputs",
                                      "restitution", "gravity", "units", "decompositions"])
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--hs", required=True)
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--np", type=int, default=1)
    args = ap.parse_args()
    ok = globals()[args.check](args)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
