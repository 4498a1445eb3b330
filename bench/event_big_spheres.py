#!/usr/bin/python3
"""Cost of big spheres and of polydispersity in the event engine: CPU time per unit simulated time.

Builds the scenes with compare.big_sphere_scene (kept in --work, made once), then times
`hardsphere run --read-data SCENE --engine event --time T` and reads loop_cpu_seconds from the
JSON. Each comparison alternates its two runs A B A B ... (--rounds rounds) so both see the same
machine load, and reports the medians and the ratio B / A (also per collision: the scene
script's phi counts the big spheres, so the small ones are more dilute with them). Prints markdown
tables:

- cost of the scene against its reference gas, with the program under test (--program);
- before/after: the same scene with --before (e.g. main's build) and --program.

  python3 -m bench.event_big_spheres --program build/standalone/hardsphere \\
      --before /path/to/main/build/standalone/hardsphere --rounds 3
"""
import argparse
import json
import os
import statistics
import subprocess

import numpy as np

from compare import big_sphere_scene
from compare.lammps_files import read_data, write_data


# name: arguments of compare.big_sphere_scene, simulated time per timed run (a few CPU seconds), and
# that of a --before run where a grid sized by a big sphere is slow. A run must last several list
# rebuilds per sphere (shell / 2 of travel) to measure their cost: big20x5's before engine has a
# shell of 2.7 and rebuilds about once per time unit.
SCENES = {
    "gas20k": (["--n", "20000", "--phi", "0.2"], 30.0, 30.0),
    "big10": (["--n", "20000", "--phi", "0.2", "--big", "1", "--big-diameter", "10", "--big-mass", "1000"], 30.0, 10.0),
    "gas80k": (["--n", "80000", "--phi", "0.2"], 8.0, 8.0),
    "big20": (["--n", "80000", "--phi", "0.2", "--big", "1", "--big-diameter", "20", "--big-mass", "1e4"], 8.0, 0.3),
    "big20x5": (["--n", "80000", "--phi", "0.2", "--big", "5", "--big-diameter", "20", "--big-mass", "1e4"], 8.0, 2.0),
    "uniform": (["--n", "20000", "--phi", "0.2", "--sizes", "uniform:0.5,1.5"], 30.0, 30.0),
    "lognormal": (["--n", "20000", "--phi", "0.2", "--sizes", "lognormal:0.25"], 30.0, 30.0),
    "lognormal_clipped": (None, 30.0, 30.0),  # the log-normal file, diameters clipped at 2 medians
}
LABEL = {
    "gas20k": "20000 unit spheres, phi 0.2",
    "big10": "same + 1 sphere D=10, M=1000",
    "gas80k": "80000 unit spheres, phi 0.2",
    "big20": "same + 1 sphere D=20, M=1e4",
    "big20x5": "same + 5 spheres D=20, M=1e4",
    "uniform": "20000, D uniform in [0.5, 1.5]",
    "lognormal": "20000, D log-normal s=0.25",
    "lognormal_clipped": "same, D clipped at 2 medians (no big sphere)",
}
AGAINST = [
    ("gas20k", "big10"),
    ("gas80k", "big20"),
    ("gas80k", "big20x5"),
    ("gas20k", "uniform"),
    ("gas20k", "lognormal"),
    ("lognormal_clipped", "lognormal"),
]


def clip_diameters(src, dst, medians=2.0):
    """Copies a data file of compare.big_sphere_scene with every diameter above `medians` median
    diameters set to that; densities are kept, so masses shrink with the volume."""
    data = read_data(src)
    data.diameter = np.minimum(data.diameter, medians * statistics.median(data.diameter.tolist()))
    write_data(dst, data)


def scene_file(work, name, seed):
    path = os.path.join(work, f"{name}_s{seed}.data")
    if not os.path.exists(path):
        args = SCENES[name][0]
        if args is None:
            return clip_diameters(scene_file(work, "lognormal", seed), path) or path
        big_sphere_scene.main([*args, "--seed", str(seed), "--out", path])
    return path


def cpu_per_time(program, data, t):
    """loop_cpu_seconds per unit simulated time and per collision of one run."""
    out = subprocess.run(
        [program, "run", "--read-data", data, "--engine", "event", "--time", repr(t), "--json", "-"],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    j = json.loads(out)
    return j["loop_cpu_seconds"] / t, j["loop_cpu_seconds"] / max(j["collisions"], 1)


def alternate(rounds, run_a, run_b):
    """Medians of (per time, per collision) of A and of B over alternating runs."""
    a, b = [], []
    for _ in range(rounds):
        a.append(run_a())
        b.append(run_b())

    def med(x):
        return statistics.median(v[0] for v in x), statistics.median(v[1] for v in x)

    return med(a), med(b)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--program", required=True, help="hardsphere under test")
    ap.add_argument("--before", help="a second hardsphere for the before/after table")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--scale", type=float, default=1.0, help="multiplies every run's simulated time")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--work", default="bench_event_big", help="directory for the scene files")
    a = ap.parse_args(argv)
    if a.rounds < 1 or not a.scale > 0:
        ap.error("--rounds must be >= 1 and --scale > 0")
    os.makedirs(a.work, exist_ok=True)
    data = {name: scene_file(a.work, name, a.seed) for name in SCENES}
    t = {name: SCENES[name][1] * a.scale for name in SCENES}

    print(f"CPU seconds per unit simulated time (median of {a.rounds} alternating rounds), {a.program}\n")
    print("| reference A | scene B | A | B | B / A | B / A per collision |")
    print("|---|---|---|---|---|---|")
    for ref, other in AGAINST:
        ma, mb = alternate(
            a.rounds,
            lambda: cpu_per_time(a.program, data[ref], t[ref]),
            lambda: cpu_per_time(a.program, data[other], t[other]),
        )
        print(
            f"| {LABEL[ref]} | {LABEL[other]} | {ma[0]:.4g} | {mb[0]:.4g} | {mb[0] / ma[0]:.3f} | {mb[1] / ma[1]:.3f} |",
            flush=True,
        )

    if a.before:
        print(f"\nBefore ({a.before}) and after ({a.program}), CPU seconds per unit simulated time\n")
        print("| scene | before | after | after / before |")
        print("|---|---|---|---|")
        for name in SCENES:
            tb = SCENES[name][2] * a.scale
            mb, ma = alternate(
                a.rounds,
                lambda: cpu_per_time(a.before, data[name], tb),
                lambda: cpu_per_time(a.program, data[name], t[name]),
            )
            print(f"| {LABEL[name]} | {mb[0]:.4g} | {ma[0]:.4g} | {ma[0] / mb[0]:.3f} |", flush=True)


if __name__ == "__main__":
    main()
