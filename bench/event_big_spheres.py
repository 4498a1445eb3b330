#!/usr/bin/python3
"""Cost of big spheres and of polydispersity in the event engine: CPU time per unit simulated time.

Builds the scenes with compare.big_sphere_scene (kept in --work when given, made once), then times
`hardsphere run --read-data SCENE --engine event --time T` and reads loop_cpu_seconds from the
JSON. Each comparison alternates its two runs A B A B ... (--rounds rounds) so both see the same
machine load, and reports the medians and the ratio B / A (also per collision: the scene
script's phi counts the big spheres, so the small ones are more dilute with them):

- cost of the scene against its reference gas, with the program under test (--hardsphere);
- before/after: the same scene with --before (e.g. main's build) and --hardsphere.

  python3 -m bench.event_big_spheres --out DIR [--build DIR] [--hardsphere PATH]
      [--before /path/to/main/build/standalone/hardsphere] [--rounds 3] [--work DIR]

Writes DIR/event_big_spheres.md and DIR/event_big_spheres.json. Speed is reported, never asserted.
"""
import os
import statistics

import numpy as np

from compare import big_sphere_scene, harness
from compare.lammps_files import read_data, write_data

# name: arguments of compare.big_sphere_scene, simulated time per timed run (a few CPU seconds), and
# that of a --before run where a grid sized by a big sphere is slow. A run must last several list
# rebuilds per sphere (shell / 2 of travel) to measure their cost: big20x5's before engine has a
# shell of 2.7 and rebuilds about once per time unit.
SCENES = {
    "gas20k": (dict(n=20000, phi=0.2), 30.0, 30.0),
    "big10": (dict(n=20000, phi=0.2, big=1, big_diameter=10.0, big_mass=1000.0), 30.0, 10.0),
    "gas80k": (dict(n=80000, phi=0.2), 8.0, 8.0),
    "big20": (dict(n=80000, phi=0.2, big=1, big_diameter=20.0, big_mass=1e4), 8.0, 0.3),
    "big20x5": (dict(n=80000, phi=0.2, big=5, big_diameter=20.0, big_mass=1e4), 8.0, 2.0),
    "uniform": (dict(n=20000, phi=0.2, sizes="uniform:0.5,1.5"), 30.0, 30.0),
    "lognormal": (dict(n=20000, phi=0.2, sizes="lognormal:0.25"), 30.0, 30.0),
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
        spec = SCENES[name][0]
        if spec is None:
            clip_diameters(scene_file(work, "lognormal", seed), path)
        else:
            big_sphere_scene.write_scene(path, big_sphere_scene.make_scene(seed=seed, **spec))
    return path


def cpu_per_time(program, data, t):
    """loop_cpu_seconds per unit simulated time and per collision of one run."""
    j = harness.hardsphere_json(program, "--read-data", data, "--engine", "event", "--time", repr(t))
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


def markdown(data, generated):
    lines = ["# Big spheres and size spread in the event engine", "", generated, "",
             f"CPU seconds per unit simulated time (`loop_cpu_seconds / time`), medians of {data['rounds']} "
             "alternating rounds A B A B; phi 0.2 counts every sphere (the small spheres around big ones are more "
             "dilute), hence also the ratio per collision.", "",
             "| reference A | scene B | A | B | B / A | B / A per collision |", "|---|---|---|---|---|---|"]
    for r in data["against"]:
        lines.append(f"| {r['a']} | {r['b']} | {r['a_per_time']:.4g} | {r['b_per_time']:.4g} | "
                     f"{r['b_per_time'] / r['a_per_time']:.3f} | {r['b_per_collision'] / r['a_per_collision']:.3f} |")
    if data["before_after"]:
        lines += ["", f"Before (`{data['before']}`) and after, CPU seconds per unit simulated time:", "",
                  "| scene | before | after | after / before |", "|---|---|---|---|"]
        lines += [f"| {r['scene']} | {r['before']:.4g} | {r['after']:.4g} | {r['after'] / r['before']:.3f} |"
                  for r in data["before_after"]]
    return "\n".join(lines)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("--before", help="a second hardsphere for the before/after table")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--scale", type=float, default=1.0, help="multiplies every run's simulated time")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args(argv)
    if a.rounds < 1 or not a.scale > 0:
        raise harness.InputError("--rounds must be >= 1 and --scale > 0")
    session = harness.Session("bench.event_big_spheres", a, argv)
    hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
    out = session.out()
    t = {name: SCENES[name][1] * a.scale for name in SCENES}
    against, before_after = [], []
    with session.workdir() as work:
        data = {name: scene_file(str(work), name, a.seed) for name in SCENES}
        for ref, other in AGAINST:
            ma, mb = alternate(a.rounds, lambda: cpu_per_time(hs, data[ref], t[ref]),
                               lambda: cpu_per_time(hs, data[other], t[other]))
            against.append(dict(a=LABEL[ref], b=LABEL[other], a_per_time=ma[0], b_per_time=mb[0],
                                a_per_collision=ma[1], b_per_collision=mb[1]))
            session.log(f"{LABEL[other]} against {LABEL[ref]}: {mb[0] / ma[0]:.3f}")
        if a.before:
            for name in SCENES:
                tb = SCENES[name][2] * a.scale
                mb, ma = alternate(a.rounds, lambda: cpu_per_time(a.before, data[name], tb),
                                   lambda: cpu_per_time(hs, data[name], t[name]))
                before_after.append(dict(scene=LABEL[name], before=mb[0], after=ma[0]))
                session.log(f"{LABEL[name]}: after / before {ma[0] / mb[0]:.3f}")
    result = dict(command=session.command, rounds=a.rounds, scale=a.scale, seed=a.seed, before=a.before,
                  against=against, before_after=before_after)
    report = session.write_report(out, "event_big_spheres", markdown(result, session.generated()), result)
    return session.finish([], report)


if __name__ == "__main__":
    harness.main(main)
