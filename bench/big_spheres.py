#!/usr/bin/python3
"""What big spheres and size spread cost the stepper, through the command line.

Builds the scenes with compare.big_sphere_scene (kept in --workdir, reused when present) and
times `hardsphere run --read-data F --steps S --json J --quiet`, taking the JSON's loop CPU time.
The variants of one comparison run alternately (A B C A B C ...) for --rounds rounds, so a load
that comes and goes hits them alike; the table gives medians of CPU seconds per step and their
ratios to the first variant of the group.

  python3 -m bench.big_spheres [--hardsphere build/standalone/hardsphere] [--before OLD_BINARY] [--rounds 5]

Groups: 20000 spheres at phi 0.2 with and without one sphere of diameter 10 (mass 1000); 80000
with and without one of diameter 20 (mass 10^4); uniform [0.5, 1.5] and log-normal (s = 0.25)
diameters against equal spheres at the same N and phi. "mono gas, poly kernel" is the gas with
diameters within 1e-6 of 1: the general kernel on the same physics. phi counts the big sphere, so
its small spheres are more dilute than the mono gas: "gas as dense as around the big sphere" is
the gas without it at their density. With --before, the big
sphere scenes also run on that binary (fewer steps, --before-steps).
"""
import argparse
import json
import os
import statistics
import subprocess

from compare import big_sphere_scene

TINY_SPREAD = "uniform:0.999999,1.000001"


def scene_file(workdir, name, **kw):
    path = os.path.join(workdir, name + ".data")
    if not os.path.exists(path):
        big_sphere_scene.write_scene(path + ".tmp", big_sphere_scene.make_scene(**kw))
        os.replace(path + ".tmp", path)
    return path


def run(binary, data, steps, workdir):
    out = os.path.join(workdir, "run.json")
    subprocess.run([binary, "run", "--read-data", data, "--steps", str(steps), "--json", out, "--quiet"],
                   check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        j = json.load(f)
    return j["loop_cpu_seconds"] / steps, j


def compare(title, variants, rounds, workdir):
    """variants: (label, binary, data, steps); prints table rows, first variant is the reference."""
    times = {v[0]: [] for v in variants}
    info = {}
    for _ in range(rounds):
        for label, binary, data, steps in variants:
            t, j = run(binary, data, steps, workdir)
            times[label].append(t)
            info[label] = j
    ref = statistics.median(times[variants[0][0]])
    for label, _, _, steps in variants:
        med = statistics.median(times[label])
        j = info[label]
        cells = "x".join(str(c) for c in j["cells_per_dim"])
        print(
            f"| {title} | {label} | {j['scene_kernel']} | {cells} | {j['skin']:.3f} | {steps} |"
            f" {j['collisions'] / steps:.0f} | {med * 1e3:.3f} | {med / ref:.2f} |"
        )
        sys.stdout.flush()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hardsphere", default=os.path.join(HERE, "..", "build", "standalone", "hardsphere"))
    ap.add_argument("--before", help="an older hardsphere binary to time on the big-sphere scenes")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--steps", type=int, default=1000, help="steps per run at N = 20000 (scaled by 20000/N)")
    ap.add_argument("--before-steps", type=int, default=50, help="steps per run of --before at N = 20000")
    ap.add_argument("--workdir", default="big_spheres_work")
    a = ap.parse_args(argv)
    if a.rounds < 3:
        sys.exit("big_spheres.py: error: --rounds must be >= 3 for a median of alternating runs")
    os.makedirs(a.workdir, exist_ok=True)
    hs = a.hardsphere

    def steps(n, base):
        return max(1, base * 20000 // n)

    print("| scene | variant | kernel | cells | skin | steps | collisions/step | CPU ms/step (median) | ratio |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n, d, m in ((20000, 10.0, 1000.0), (80000, 20.0, 1e4)):
        gas = scene_file(a.workdir, f"mono_{n}", n=n, phi=0.2)
        tiny = scene_file(a.workdir, f"tiny_{n}", n=n, phi=0.2, sizes=TINY_SPREAD)
        big = scene_file(a.workdir, f"big_{n}_d{d:g}", n=n, phi=0.2, big=1, big_diameter=d, big_mass=m)
        # phi counts the big sphere too: the small spheres of `big` are as dense as this gas.
        same = scene_file(a.workdir, f"same_{n}_d{d:g}", n=n, phi=0.2 * n / (n + d**3))
        same_tiny = scene_file(a.workdir, f"same_tiny_{n}_d{d:g}", n=n, phi=0.2 * n / (n + d**3), sizes=TINY_SPREAD)
        s = steps(n, a.steps)
        title = f"N {n}, phi 0.2, one D={d:g} M={m:g}"
        compare(
            title,
            [
                ("mono gas", hs, gas, s),
                ("mono gas, poly kernel", hs, tiny, s),
                ("gas as dense as around the big sphere", hs, same, s),
                ("the same, poly kernel", hs, same_tiny, s),
                ("with big sphere", hs, big, s),
            ],
            a.rounds,
            a.workdir,
        )
        if a.before:
            sb = steps(n, a.before_steps)
            compare(
                title + ", before/after",
                [("before", a.before, big, sb), ("after", hs, big, sb)],
                a.rounds,
                a.workdir,
            )
    n = 20000
    gas = scene_file(a.workdir, f"mono_{n}", n=n, phi=0.2)
    for name, sizes in (("uniform [0.5, 1.5]", "uniform:0.5,1.5"), ("log-normal s 0.25", "lognormal:0.25")):
        poly = scene_file(a.workdir, f"{sizes.replace(':', '_').replace(',', '_')}_{n}", n=n, phi=0.2, sizes=sizes)
        variants = [("mono gas", hs, gas, a.steps), (name, hs, poly, a.steps)]
        compare(f"N {n}, phi 0.2, {name}", variants, a.rounds, a.workdir)


if __name__ == "__main__":
    main()
