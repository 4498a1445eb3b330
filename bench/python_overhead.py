"""The Python module's loop against the CLI's on the same state (docs/python.md#performance).

    python3 -m bench.python_overhead --out DIR [--build DIR] [--repeats 5]

Alternates CLI and Python runs of one data file (stepper and event engine), takes the median of
each side's loop_cpu_seconds (the CLI's JSON key; the module's counts its whole run() loop,
chunking, GIL round trips and signal checks included) and writes the ratio into
DIR/python_overhead.md and DIR/python_overhead.json. The module is BUILD/python/hardsphere.
Reported, never asserted."""
import json
import statistics
import sys

from compare import harness


def markdown(data, generated):
    lines = ["# The Python module's loop against the CLI's", "", generated, "",
             f"{data['n']} spheres at phi {data['phi']}, {data['repeats']} alternating runs of each side, medians of "
             "`loop_cpu_seconds` (the module's includes its chunking, GIL round trips and signal checks).", "",
             "| engine | run | CLI loop_cpu_seconds | Python run() | Python / CLI |", "|---|---|---|---|---|"]
    lines += [f"| {r['engine']} | {r['run']} | {r['cli']:.3f} | {r['python']:.3f} | {r['python'] / r['cli']:.3f} |"
              for r in data["rows"]]
    return "\n".join(lines)


def main(argv=None):
    ap = harness.parser(__doc__.splitlines()[0], programs=("hardsphere",))
    ap.add_argument("--n", type=int, default=8000)
    ap.add_argument("--phi", type=float, default=0.45)
    ap.add_argument("--steps", type=int, default=400, help="stepper steps per run")
    ap.add_argument("--time", type=float, default=2.0, help="event engine simulated time per run")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    session = harness.Session("bench.python_overhead", args, argv)
    tools = harness.tools(args, need=("hardsphere",))
    out = session.out()
    sys.path.insert(0, str(tools["build"] / "python"))
    try:
        import hardsphere as hs
    except ImportError as e:
        raise harness.InputError(f"no Python module in {tools['build'] / 'python'} ({e})") from None
    rows = []
    with session.workdir() as tmp:
        data = str(tmp / "start.data")
        hs.System.random(n=args.n, phi=args.phi, seed=1).write_data(data)
        start = hs.System.from_data(data)
        cases = [("stepper", ["--steps", args.steps], lambda: hs.Stepper(start), {"steps": args.steps}),
                 ("event", ["--engine", "event", "--time", args.time, "--blocks", 1], lambda: hs.EventEngine(start),
                  {"time": args.time})]
        for name, cli_args, make, run_args in cases:
            cli_t, py_t = [], []
            for _ in range(args.repeats):
                cli = harness.run_program([tools["hardsphere"], "run", "--read-data", data, *cli_args, "--json", "-"])
                cli_t.append(json.loads(cli.stdout)["loop_cpu_seconds"])
                sim = make()
                sim.run(**run_args)
                py_t.append(sim.observables()["loop_cpu_seconds"])
            c, p = statistics.median(cli_t), statistics.median(py_t)
            rows.append(dict(engine=name, run=f"{args.steps} steps" if name == "stepper" else f"time {args.time}",
                             cli=c, python=p, cli_runs=cli_t, python_runs=py_t))
            session.log(f"{name}: Python / CLI {p / c:.3f}")
    result = dict(command=session.command, n=args.n, phi=args.phi, repeats=args.repeats, rows=rows)
    report = session.write_report(out, "python_overhead", markdown(result, session.generated()), result)
    return session.finish([], report)


if __name__ == "__main__":
    harness.main(main)
