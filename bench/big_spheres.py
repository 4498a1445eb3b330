#!/usr/bin/python3
"""What big spheres and size spread cost the stepper, through the command line.

Builds the scenes with compare.big_sphere_scene (kept in --work and reused when given) and times
`hardsphere run --read-data F --steps S --json J --quiet`, taking the JSON's loop CPU time. The
variants of one comparison run alternately (A B C A B C ...) for --rounds rounds, so a load that
comes and goes hits them alike; the report gives medians of CPU seconds per step and their ratios
to the first variant of the group.

  python3 -m bench.big_spheres --out DIR [--build DIR] [--hardsphere PATH] [--before OLD_BINARY]
      [--rounds 5] [--work DIR]

Groups: 20000 spheres at phi 0.2 with and without one sphere of diameter 10 (mass 1000); 80000
with and without one of diameter 20 (mass 10^4); uniform [0.5, 1.5] and log-normal (s = 0.25)
diameters against equal spheres at the same N and phi; the log-normal gas against itself with its
diameters clipped at 2 medians (no big sphere). "mono gas, poly kernel" is the gas with
diameters within 1e-6 of 1: the general kernel on the same physics. phi counts the big sphere, so
its small spheres are more dilute than the mono gas: "gas as dense as around the big sphere" is
the gas without it at their density. With --before, the big sphere scenes also run on that binary
(fewer steps, --before-steps). Writes DIR/big_spheres.md and DIR/big_spheres.json. Speed is
reported, never asserted.
"""
import os
import statistics

from bench.event_big_spheres import clip_diameters
from compare import big_sphere_scene, harness

TINY_SPREAD = "uniform:0.999999,1.000001"


def scene_file(workdir, name, **kw):
    path = os.path.join(workdir, name + ".data")
    if not os.path.exists(path):
        big_sphere_scene.write_scene(path + ".tmp", big_sphere_scene.make_scene(**kw))
        os.replace(path + ".tmp", path)
    return path


def run(binary, data, steps, workdir):
    j = harness.hardsphere_json(binary, "--read-data", data, "--steps", steps, "--quiet", cwd=workdir)
    return j["loop_cpu_seconds"] / steps, j


def compare(title, variants, rounds, workdir, log):
    """variants: (label, binary, data, steps); the rows of one group, the first variant the reference."""
    times = {v[0]: [] for v in variants}
    info = {}
    for _ in range(rounds):
        for label, binary, data, steps in variants:
            t, j = run(binary, data, steps, workdir)
            times[label].append(t)
            info[label] = j
    ref = statistics.median(times[variants[0][0]])
    rows = []
    for label, _, _, steps in variants:
        med = statistics.median(times[label])
        j = info[label]
        rows.append(dict(group=title, variant=label, kernel=j["scene_kernel"], cells=j["cells_per_dim"],
                         skin=j["skin"], steps=steps, collisions_per_step=j["collisions"] / steps,
                         cpu_seconds_per_step=times[label], median=med, ratio=med / ref))
        log(f"{title}: {label}: {med * 1e3:.3f} ms per step, {med / ref:.2f}x")
    return rows


def markdown(data, generated):
    lines = ["# What big spheres and size spread cost the stepper", "", generated, "",
             f"CPU time of the step loop (`loop_cpu_seconds`), medians of {data['rounds']} alternating rounds; ratio "
             "to the first variant of each group. phi 0.2 counts every sphere.", "",
             "| scene | variant | kernel | cells | skin | steps | collisions/step | CPU ms/step (median) | ratio |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in data["rows"]:
        lines.append(f"| {r['group']} | {r['variant']} | {r['kernel']} | {'x'.join(map(str, r['cells']))} | "
                     f"{r['skin']:.3f} | {r['steps']} | {r['collisions_per_step']:.0f} | {r['median'] * 1e3:.3f} | "
                     f"{r['ratio']:.2f} |")
    return "\n".join(lines)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("--before", help="an older hardsphere binary to time on the big-sphere scenes")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--steps", type=int, default=1000, help="steps per run at N = 20000 (scaled by 20000/N)")
    ap.add_argument("--before-steps", type=int, default=50, help="steps per run of --before at N = 20000")
    a = ap.parse_args(argv)
    if a.rounds < 3:
        raise harness.InputError("--rounds must be >= 3 for a median of alternating runs")
    session = harness.Session("bench.big_spheres", a, argv)
    hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
    out = session.out()

    def steps(n, base):
        return max(1, base * 20000 // n)

    rows = []
    with session.workdir() as work:
        for n, d, m in ((20000, 10.0, 1000.0), (80000, 20.0, 1e4)):
            gas = scene_file(work, f"mono_{n}", n=n, phi=0.2)
            tiny = scene_file(work, f"tiny_{n}", n=n, phi=0.2, sizes=TINY_SPREAD)
            big = scene_file(work, f"big_{n}_d{d:g}", n=n, phi=0.2, big=1, big_diameter=d, big_mass=m)
            # phi counts the big sphere too: the small spheres of `big` are as dense as this gas.
            same = scene_file(work, f"same_{n}_d{d:g}", n=n, phi=0.2 * n / (n + d**3))
            same_tiny = scene_file(work, f"same_tiny_{n}_d{d:g}", n=n, phi=0.2 * n / (n + d**3), sizes=TINY_SPREAD)
            s = steps(n, a.steps)
            title = f"N {n}, phi 0.2, one D={d:g} M={m:g}"
            rows += compare(title, [("mono gas", hs, gas, s), ("mono gas, poly kernel", hs, tiny, s),
                                    ("gas as dense as around the big sphere", hs, same, s),
                                    ("the same, poly kernel", hs, same_tiny, s), ("with big sphere", hs, big, s)],
                            a.rounds, work, session.log)
            if a.before:
                sb = steps(n, a.before_steps)
                rows += compare(title + ", before/after", [("before", a.before, big, sb), ("after", hs, big, sb)],
                                a.rounds, work, session.log)
        n = 20000
        gas = scene_file(work, f"mono_{n}", n=n, phi=0.2)
        for name, sizes in (("uniform [0.5, 1.5]", "uniform:0.5,1.5"), ("log-normal s 0.25", "lognormal:0.25")):
            poly = scene_file(work, f"{sizes.replace(':', '_').replace(',', '_')}_{n}", n=n, phi=0.2, sizes=sizes)
            rows += compare(f"N {n}, phi 0.2, {name}", [("mono gas", hs, gas, a.steps), (name, hs, poly, a.steps)],
                            a.rounds, work, session.log)
        # The log-normal gas against itself with the diameters above 2 medians clipped: no big sphere.
        clipped = os.path.join(work, f"lognormal_clipped_{n}.data")
        if not os.path.exists(clipped):
            clip_diameters(poly, clipped)
        rows += compare(f"N {n}, phi 0.2, log-normal s 0.25 against the same clipped at 2 medians",
                        [("clipped (no big sphere)", hs, clipped, a.steps), ("log-normal s 0.25", hs, poly, a.steps)],
                        a.rounds, work, session.log)
    data = dict(command=session.command, rounds=a.rounds, rows=rows)
    report = session.write_report(out, "big_spheres", markdown(data, session.generated()), data)
    return session.finish([], report)


if __name__ == "__main__":
    harness.main(main)
