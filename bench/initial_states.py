#!/usr/bin/python3
"""Time and structure of initial states made by the hardsphere program (docs/initial_states.md).

For each packing fraction, runs
    HARDSPHERE run --n N --phi PHI --seed K --init INIT --boundary B --steps 0
for seeds K = 1..RUNS and records how many were made and the wall time (process start included).
For seed 1 it also writes the state once more (untimed), measures the compressibility factor Z over
--time 0.2 of the event engine from it, and its structure (compare.packing_structure).

  python3 -m bench.initial_states --out DIR --n 4000 --phi 0.58 0.60 [--runs 3] [--init dense]
      [--boundary p] [--build DIR] [--hardsphere PATH]
  python3 -m bench.initial_states --out DIR --from-json

DIR/initial_states.json keeps the rows of every call (one table per N, init and boundary; a call
replaces the rows it measured), DIR/initial_states.md shows them all; --from-json only renders the
markdown again.
"""
import json
import statistics
import time

from compare import harness
from compare import packing_structure as structure


def run(hs, *args):
    start = time.perf_counter()
    p = harness.run_program([hs, "run", *args], expect=None)
    return time.perf_counter() - start, p


def measure(hs, a, phi, tmp):
    common = ["--n", a.n, "--phi", phi, "--init", a.init, "--boundary", a.boundary, "--steps", 0]
    times, made, note = [], 0, ""
    for seed in range(1, a.runs + 1):
        t, p = run(hs, *common, "--seed", seed)
        times.append(t)
        made += p.returncode == 0
        if p.returncode != 0:
            note = p.stderr.strip().splitlines()[-1].split("error: ")[-1]
    row = dict(n=a.n, phi=phi, init=a.init, boundary=a.boundary, runs=a.runs, made=made, seconds=times, note=note)
    data = tmp / "state.data"
    if made and run(hs, *common, "--seed", 1, "--write-data", data)[1].returncode == 0:
        _, p = run(hs, "--read-data", data, "--boundary", a.boundary, "--engine", "event", "--time", 0.2,
                   "--json", "-")
        if p.returncode == 0:
            row["Z"] = json.loads(p.stdout)["compressibility_factor"]
        row["structure"] = structure.analyse(*structure.read_packing(data), structure.parse_boundary(a.boundary))
    return row


def markdown(store):
    rows = store.rows("states")
    lines = ["# Initial states: time and structure", "",
             "Wall time of `hardsphere run --n N --phi PHI --seed K --steps 0` (process start included), median over "
             "seeds 1..R (range in brackets); for seed 1 the compressibility factor Z over the first 0.2 time units "
             "of the event engine and the structure (`compare.packing_structure`): global bond order Q6 "
             "(neighbours within 1.4 diameters; FCC 0.575, an amorphous packing ~0), the fraction of crystal-like "
             "spheres (ten Wolde et al. 1996; FCC 1.0), g(r) at sqrt(3) and 2 diameters.", "",
             "Measured by " + "; ".join(harness.measured_by(rows)) + ".", ""]
    groups = {}
    for r in rows:
        groups.setdefault((r["n"], r["init"], r["boundary"]), []).append(r)
    for (n, init, boundary), rs in groups.items():
        where = "periodic" if boundary == "p" else f"boundary {boundary}"
        lines += [f"## N = {n}, {where}, `--init {init}`", "",
                  "| phi | made | time s | Z | Q6 | crystal-like | g(sqrt3) | g(2) | note |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for r in sorted(rs, key=lambda r: r["phi"]):
            t = r["seconds"]
            spread = f"{statistics.median(t):.2f} ({min(t):.2f}-{max(t):.2f})"
            s = r.get("structure")
            cols = [f"{r['Z']:.1f}" if "Z" in r else "", f"{s['Q6']:.3f}" if s else "",
                    f"{s['crystal-like']:.3f}" if s else "", f"{s['g(sqrt3)']:.2f}" if s else "",
                    f"{s['g(2)']:.2f}" if s else ""]
            lines.append(f"| {r['phi']} | {r['made']}/{r['runs']} | {spread} | " + " | ".join(cols) + f" | {r['note']} |")
        lines.append("")
    return "\n".join(lines)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",))
    ap.add_argument("--n", type=int)
    ap.add_argument("--phi", type=float, nargs="+")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--init", default="auto")
    ap.add_argument("--boundary", default="p")
    ap.add_argument("--from-json", action="store_true", help="render DIR/initial_states.md from its JSON only")
    a = ap.parse_args(argv)
    session = harness.Session("bench.initial_states", a, argv)
    store = harness.RowStore(session.out(), "initial_states")
    if not a.from_json:
        if not a.n or not a.phi:
            raise harness.InputError("--n and --phi are needed (or --from-json)")
        hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
        with session.workdir() as tmp:
            for phi in a.phi:
                row = measure(hs, a, phi, tmp)
                store.put("states", (a.n, a.init, a.boundary, phi), row, session)
                session.log(f"N {a.n} phi {phi}: made {row['made']}/{a.runs}, median "
                            f"{statistics.median(row['seconds']):.2f} s")
    return session.finish([], store.render(markdown(store)))


if __name__ == "__main__":
    harness.main(main)
