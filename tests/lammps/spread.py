"""The spread of a LAMMPS check's statistical quantities over independent runs: the tolerances of
FEATURE.yaml come from it (at least 4 sigma, the measurement in a comment beside the check).

A case compares a run that parts from the standalone stepper by rounding (2 ranks, the owned +
ghost path, other units) with the standalone's run of the same state: after a chaotic divergence
the two are independent samples of the same process. Each seed makes another initial state (the
case's `hardsphere run ... --steps 0` states get --seed S) and runs the case's own function, so
the quantities are exactly those the test checks. Printed per quantity of a rel, abs, below or
above check (its 2-rank form under --np 2): mean and standard deviation of value / ref - 1 (rel),
value - ref (abs) or log10(value) (below / above, for round-off amplified by chaos), the largest
deviation, and the bound mean + 4 sigma (and the absolute bound |mean| + 4 sigma for rel / abs).
For rel checks also the spread of the reference itself over the seeds (sd of ref / mean - 1):
two runs that have fully parted differ by sqrt(2) times the spread of one given its start, which
the spread over starts bounds, so 4 sqrt(2) ref sd holds even where no seed had parted yet.

    python3 -m tests.lammps.spread FEATURE CASE --lmp PATH --hs PATH [--plugin PATH]
                                   [--np 2 --mpirun PATH] [--seeds 20]
"""
import argparse
import importlib
import math
import statistics
import sys
import tempfile
from pathlib import Path

from tests.lammps.lammps_runner import Context, _resolve, applies


def deviation(check, value, refs):
    """(kind, number) for one check of one run."""
    if "rel" in check:
        return "rel", value / _resolve(check["ref"], refs) - 1
    if "abs" in check:
        return "abs", value - _resolve(check["ref"], refs)
    if "below" in check or "above" in check:
        return "log10", math.log10(abs(value)) if value else -math.inf
    return None, None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("feature")
    ap.add_argument("case")
    ap.add_argument("--lmp", required=True)
    ap.add_argument("--plugin", default="")
    ap.add_argument("--hs", required=True)
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--seeds", type=int, default=20)
    args = ap.parse_args(argv)
    args.lmp, args.hs = str(Path(args.lmp).resolve()), str(Path(args.hs).resolve())
    cases = importlib.import_module(f"tests.lammps.{args.feature}").cases
    entry = cases.spec["cases"][args.case]
    checks = {q: (c.get("mpi", c) if args.np > 1 else c) for q, c in entry["quantities"].items()
              if applies(c, args.np > 1)}
    samples, ref_values = {}, {}
    for seed in range(1, args.seeds + 1):
        with tempfile.TemporaryDirectory() as work:
            ctx = Context(args, work)
            made = []
            plain = ctx.standalone

            def seeded(*opts, _plain=plain, _seed=seed, _made=made):
                # A state made from scratch (not read) gets the seed.
                if "--read-data" not in map(str, opts):
                    opts = (*opts, "--seed", _seed)
                    _made.append(opts)
                return _plain(*opts)
            ctx.standalone = seeded
            measured, refs = cases.function(args.case)(ctx, entry)
            if not made:
                sys.exit(f"{args.feature}/{args.case}: makes no state with `hardsphere run`: seeds change nothing")
            for q, check in checks.items():
                kind, d = deviation(check, measured.get(q), refs) if q in measured else (None, None)
                if kind:
                    samples.setdefault(q, (kind, []))[1].append(d)
                if kind == "rel":
                    ref_values.setdefault(q, []).append(_resolve(check["ref"], refs))
        print(f"seed {seed}: " + ", ".join(f"{q} {v[1][-1]:.3g}" for q, v in samples.items()), flush=True)
    print(f"{args.feature}/{args.case} on {args.np} rank(s), {args.seeds} seeds:")
    for q, (kind, xs) in samples.items():
        finite = [x for x in xs if math.isfinite(x)]
        mean = statistics.fmean(finite) if finite else math.nan
        sd = statistics.stdev(finite) if len(finite) > 1 else math.nan
        # rel / abs: the largest deviation; log10: the largest value
        largest = (max(finite) if kind == "log10" else max(finite, key=abs)) if finite else math.nan
        bound = f"|mean| + 4 sd = {abs(mean) + 4 * sd:.3g}" if kind != "log10" else \
            f"mean + 4 sd = {mean + 4 * sd:.3g} (value {10 ** (mean + 4 * sd):.3g})"
        print(f"  {q} ({kind}): mean {mean:.3g}, sd {sd:.3g}, largest {largest:.3g}, {bound}"
              + (f", {len(xs) - len(finite)} zero" if len(finite) < len(xs) else ""))
        if q in ref_values and len(ref_values[q]) > 1:
            refs_q = ref_values[q]
            ref_sd = statistics.stdev(refs_q) / abs(statistics.fmean(refs_q))
            print(f"    ref sd {ref_sd:.3g} over the seeds: 4 sqrt(2) ref sd = {4 * math.sqrt(2) * ref_sd:.3g}")


if __name__ == "__main__":
    main()
