#!/usr/bin/env python3
"""How good is --cells auto? For each scene, the stepper's loop CPU time with the automatic grid
against a sweep of manual grids (K cells per axis), medians of alternating rounds; writes
DIR/auto_cells.md and DIR/auto_cells.json with auto / best. Speed is reported, never asserted.

  python3 -m bench.auto_cells --out DIR [--build DIR] [--hardsphere PATH] [--rounds 3] [--quick]
"""
import dataclasses
import math
import statistics
from pathlib import Path

import numpy as np

from compare import harness
from compare.big_sphere_scene import make_scene, write_scene
from compare.lammps_files import read_data, write_data

# name, how to make the state, steps, dt
SCENES = [
    ("mono phi 0.05", dict(n=8000, phi=0.05), 200, 0.01),
    ("mono phi 0.2", dict(n=8000, phi=0.2), 200, 0.01),
    ("mono phi 0.45", dict(n=8000, phi=0.45), 100, 0.01),
    ("mono phi 0.2, long steps (dt 0.1)", dict(n=8000, phi=0.2), 40, 0.1),
    ("lognormal sizes 0.25, phi 0.2", dict(n=8000, phi=0.2, sizes="lognormal:0.25"), 100, 0.01),
    ("one big sphere d 10, mass 1000, phi 0.2", dict(n=8000, phi=0.2, big=1, big_diameter=10, big_mass=1000), 100,
     0.01),
    ("one big sphere d 20, phi 0.2", dict(n=20000, phi=0.2, big=1, big_diameter=20, big_mass=8000), 50, 0.01),
    ("one light fast big sphere d 10 (speed 5000), phi 0.12",
     dict(n=3864, phi=0.12, big=1, big_diameter=10, big_mass=1e-8 * math.pi / 6 * 1000, fast=5000), 20, 0.01),
    ("one fast unit sphere (speed 1000), phi 0.2", dict(n=8000, phi=0.2, fast=1000), 20, 0.01),
]


def state(hs, tmp, name, spec):
    spec = dict(spec)
    fast = spec.pop("fast", None)
    path = Path(tmp) / (name.replace(" ", "_").replace(",", "").replace("(", "").replace(")", "") + ".data")
    if set(spec) == {"n", "phi"}:
        # Equal spheres from the program's own generator: random placement (make_scene) stops short
        # of phi 0.45 (random sequential addition jams near 0.38).
        harness.hardsphere_json(hs, "--quiet", "--n", spec["n"], "--phi", spec["phi"], "--seed", 3, "--steps", 0,
                                "--write-data", path)
    else:
        write_scene(path, make_scene(seed=3, **spec))
    if fast:
        d = read_data(path)
        v = d.vel.copy()
        v[0] = np.array([0.6, 0.64, 0.48]) * fast
        write_data(path, dataclasses.replace(d, vel=v))
    return path


def loop_cpu(hs, data, steps, dt, cells):
    try:
        j = harness.hardsphere_json(hs, "--quiet", "--read-data", data, "--steps", steps, "--dt", dt, "--cells", cells)
    except harness.ProgramError:
        return None, None  # a grid too fine for the largest sphere is refused
    return j["loop_cpu_seconds"], j["cells_per_dim"][0]


def markdown(data, generated):
    lines = ["# How good is `--cells auto`", "", generated, "",
             f"The stepper's loop CPU time (s) with the automatic grid against manual grids of K cells per axis, "
             f"medians of {data['rounds']} alternating rounds.", "",
             "| scene | auto grid | auto (s) | best manual grid | best (s) | auto / best |", "|---|---|---|---|---|---|"]
    lines += [f"| {r['scene']} | {r['auto_k']} | {r['auto']:.3f} | {r['best_k']} | {r['best']:.3f} | "
              f"{r['auto'] / r['best']:.2f} |" for r in data["rows"]]
    return "\n".join(lines)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="one round, three scenes")
    a = ap.parse_args(argv)
    session = harness.Session("bench.auto_cells", a, argv)
    hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
    out = session.out()
    scenes = SCENES[:1] + SCENES[-2:] if a.quick else SCENES
    rounds = 1 if a.quick else a.rounds
    rows = []
    with session.workdir() as tmp:
        for name, spec, steps, dt in scenes:
            data = state(hs, tmp, name, spec)
            _, k_auto = loop_cpu(hs, data, 1, dt, "auto")
            grids = sorted({k for k in [1, 2, 3, 4, 6, 8, 11, 16, 23, 32] + [k_auto - 2, k_auto + 2] if k >= 1})
            times = {"auto": [], **{str(k): [] for k in grids}}
            for _ in range(rounds):  # alternating, so the machine's drift hits every grid alike
                for c in times:
                    t, _ = loop_cpu(hs, data, steps, dt, c)
                    if t is not None:
                        times[c].append(t)
            med = {c: statistics.median(v) for c, v in times.items() if v}
            best = min((c for c in med if c != "auto"), key=med.get)
            rows.append(dict(scene=name, auto_k=k_auto, auto=med["auto"], best_k=int(best), best=med[best],
                             medians=med))
            session.log(f"{name}: auto / best {med['auto'] / med[best]:.2f}")
    result = dict(command=session.command, rounds=rounds, rows=rows)
    report = session.write_report(out, "auto_cells", markdown(result, session.generated()), result)
    return session.finish([], report)


if __name__ == "__main__":
    harness.main(main)
