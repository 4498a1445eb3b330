#!/usr/bin/env python3
"""LAMMPS styles (fix hardsphere, pair_style hardsphere) against the standalone stepper.

Usage: lammps_checks.py CHECK --lmp PATH --hs PATH [--mpirun PATH] [--np N]
CHECK: identical | conservation | errors | runs
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


def thermo(out):
    """Rows of the last thermo block as dicts of floats."""
    lines = out.splitlines()
    rows, head = [], None
    for line in lines:
        s = line.split()
        if s and s[0] == "Step":
            head, rows = s, []
        elif head and len(s) == len(head):
            try:
                rows.append(dict(zip(head, map(float, s))))
            except ValueError:
                head = None
        elif head and s and s[0] == "Loop":
            head = None
    return rows


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


def check(cond, msg):
    print(("ok:   " if cond else "FAIL: ") + msg)
    return bool(cond)


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
        box, xs, vs = read_data(os.path.join(d, "sa.data"))
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
        _, xl, vl = read_data(os.path.join(d, "lmp.data"))
        dx = xl - xs
        dx -= box * np.round(dx / box)
        ok &= check(np.abs(dx).max() < 1e-6 and np.abs(vl - vs).max() < 1e-6,
                    tag + f"final state max |dx| {np.abs(dx).max():.2e}, max |dv| {np.abs(vl - vs).max():.2e} < 1e-6")
        ok &= check(last["f_hs[6]"] == 0, tag + "every ghost agreed with its owner (no step re-run for all atoms)")
        # Thermo pressure averaged over every step = n T + W/(3 V t): the standalone's pressure.
        ok &= check(abs(last["f_pav"] / ref["pressure"] - 1) < 1e-6, tag + f"<press> {last['f_pav']:.10g} vs standalone {ref['pressure']:.10g}")

        # `newton off` (recommended in docs/lammps.md: LAMMPS then skips its reverse communication
        # of forces) changes LAMMPS's ghost bookkeeping, not the result.
        script_n = script.replace("units lj", "units lj\nnewton off").replace("write_data lmp.data", "write_data lmp_n.data")
        rc, out = run_lmp(args, script_n, d, np_=args.np)
        last_n = thermo(out)[-1]
        _, xn, vn = read_data(os.path.join(d, "lmp_n.data"))
        dxn = xn - xs
        dxn -= box * np.round(dxn / box)
        ok &= check(last_n["f_hs[1]"] == ref["collisions"] and np.abs(dxn).max() < 1e-6 and np.abs(vn - vs).max() < 1e-6,
                    tag + f"newton off: collisions {last_n['f_hs[1]']:.0f} == standalone {ref['collisions']}, "
                    f"max |dx| {np.abs(dxn).max():.2e}, max |dv| {np.abs(vn - vs).max():.2e} < 1e-6")

        # The owned + ghost path (MPI's; 'path ghosts' forces it in serial) with a ghost shell
        # only one neighbour cutoff deep ('ghost user' keeps LAMMPS's default): collision chains
        # run past it, ghost copies disagree with their owners, and those steps must be re-run
        # for all atoms; the result is still the stepper's, energy exact.
        script_g = HEADER.format(data="init.data", skin=0.5, dt=0.01).replace(
            "fix hs all hardsphere", "fix hs all hardsphere ghost user path ghosts") + """
thermo_style custom step ke f_hs[1] f_hs[6]
thermo_modify format float %.17g
thermo 200
run 200
"""
        rc, out = run_lmp(args, script_g, d, np_=args.np)
        rows_g = thermo(out)
        ok &= check(rows_g[-1]["f_hs[6]"] > 0, tag + f"thin ghost shell: {rows_g[-1]['f_hs[6]']:.0f} steps re-run for all atoms (> 0)")
        ok &= check(rows_g[-1]["f_hs[1]"] == ref["collisions"],
                    tag + f"thin ghost shell: collisions {rows_g[-1]['f_hs[1]']:.0f} == standalone {ref['collisions']}")
        ok &= check(abs(rows_g[-1]["KinEng"] / rows_g[0]["KinEng"] - 1) < 1e-12, tag + "thin ghost shell: energy kept to 1e-12")

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
        _, xs, vs = read_data(os.path.join(d, "sa_poly.data"))
        _, xl, vl = read_data(os.path.join(d, "lmp_poly.data"))
        box_p = read_data(os.path.join(d, "poly.data"))[0]
        dx = xl - xs
        dx[:, :2] -= box_p[:2] * np.round(dx[:, :2] / box_p[:2])  # z has walls: no wrapping
        ok &= check(np.abs(dx).max() < 1e-6 and np.abs(vl - vs).max() < 1e-6,
                    tag + f"mixture+walls: max |dx| {np.abs(dx).max():.2e}, max |dv| {np.abs(vl - vs).max():.2e} < 1e-6")

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


def errors(args):
    """Bad inputs end with a LAMMPS error naming what to change."""
    ok = True
    with tempfile.TemporaryDirectory() as d:
        standalone(args, d, "--n", "100", "--phi", "0.2", "--steps", "0", "--write-data", "init.data")
        base = HEADER.format(data="init.data", skin=0.5, dt=0.01)
        cases = {
            "wrong atom style": ("units lj\natom_style atomic\nregion b block 0 5 0 5 0 5\ncreate_box 1 b\n"
                                 "create_atoms 1 single 1 1 1\nmass 1 1\npair_style hardsphere\npair_coeff * * 1.0\n"
                                 "fix hs all hardsphere\nrun 1\n", "atom_style sphere"),
            "pair without fix": (base.replace("fix hs all hardsphere\n", "fix nve all nve/sphere\n") + "run 1\n",
                                 "add 'fix ID all hardsphere'"),
            "fix without pair": (base.replace("pair_style hardsphere\npair_coeff * *\n", "") + "run 1\n",
                                 "needs 'pair_style hardsphere'"),
            "overlapping atoms": (base + "set atom 1 x 0.0 y 0.0 z 0.0\nset atom 2 x 0.3 y 0.0 z 0.0\nrun 1\n",
                                  "overlap"),
            "dt too large": (HEADER.format(data="init.data", skin=0.5, dt=0.2) + "run 1\n", "timestep too large"),
            "neigh_modify delay": (base + "neigh_modify every 1 delay 5\nrun 1\n", "neigh_modify every 1 delay 0"),
            "diameter too small": (base + "pair_coeff * * 0.5\nrun 1\n", "raise that pair_coeff diameter"),
            "changing box": (base + "fix d all deform 1 x scale 1.1\nrun 1\n", "needs a fixed box"),
        }
        for name, (script, phrase) in cases.items():
            rc, out = run_lmp(args, script, d, expect_ok=False)
            err = [l for l in out.splitlines() if "ERROR" in l]
            ok &= check(rc != 0 and err and phrase in " ".join(err), f"{name}: {err[:1]}")
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("check", choices=["identical", "conservation", "errors", "runs"])
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--hs", required=True)
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--np", type=int, default=1)
    args = ap.parse_args()
    ok = globals()[args.check](args)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
