"""The Python module's loop against the CLI's on the same state (docs/python.md#performance).

    PYTHONPATH=build/python:. /usr/bin/python3 -m bench.python_overhead --build build

Alternates CLI and Python runs of one data file (stepper and event engine), takes the median of
each side's loop_cpu_seconds (the CLI's JSON key; the module's counts its whole run() loop,
chunking, GIL round trips and signal checks included) and prints the ratio. Reported, never
asserted."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default="build", help="build directory (standalone/hardsphere, python/)")
    ap.add_argument("--n", type=int, default=8000)
    ap.add_argument("--phi", type=float, default=0.45)
    ap.add_argument("--steps", type=int, default=400, help="stepper steps per run")
    ap.add_argument("--time", type=float, default=2.0, help="event engine simulated time per run")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    sys.path.insert(0, os.path.join(args.build, "python"))
    import hardsphere as hs

    exe = os.path.join(args.build, "standalone", "hardsphere")
    with tempfile.TemporaryDirectory() as tmp:
        data = os.path.join(tmp, "start.data")
        hs.System.random(n=args.n, phi=args.phi, seed=1).write_data(data)
        start = hs.System.from_data(data)
        cases = [("stepper", ["--steps", args.steps], lambda: hs.Stepper(start), {"steps": args.steps}),
                 ("event", ["--engine", "event", "--time", args.time, "--blocks", 1], lambda: hs.EventEngine(start),
                  {"time": args.time})]
        print(f"{args.n} spheres at phi {args.phi}, {args.repeats} alternating runs each (median CPU seconds)\n")
        print(f"| engine | run | CLI loop_cpu_seconds | Python run() | Python / CLI |")
        print(f"|---|---|---|---|---|")
        for name, cli_args, make, run_args in cases:
            cli_t, py_t = [], []
            for _ in range(args.repeats):
                out = subprocess.run([exe, "run", "--read-data", data, *map(str, cli_args), "--json", "-"],
                                     capture_output=True, text=True, check=True).stdout
                cli_t.append(json.loads(out)["loop_cpu_seconds"])
                sim = make()
                sim.run(**run_args)
                py_t.append(sim.observables()["loop_cpu_seconds"])
            c, p = statistics.median(cli_t), statistics.median(py_t)
            what = f"{args.steps} steps" if name == "stepper" else f"time {args.time}"
            print(f"| {name} | {what} | {c:.3f} | {p:.3f} | {p / c:.3f} |")


if __name__ == "__main__":
    main()
