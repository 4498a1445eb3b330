#!/usr/bin/env python3
"""Stress suite: hard cases for both engines, each with a pass criterion.

    python3 -m tests.stress.stress --hardsphere PATH [--quick] [--table FILE] [--only NAME ...]

(from the repository root; ctest stress_quick runs it with --quick)

Every case runs the `hardsphere` program on a generated state and checks what a correct hard-sphere
simulation must give: energy and momentum kept, no overlap, no NaN, and the case's own criterion
(an analytic result, agreement with the other engine, a refusal). --quick runs the reduced set that
ctest runs (label `stress`); without it the full set runs (minutes) and --table writes the
markdown table of docs/reports/stress.md (and stress.json beside it). Exit status 1 if any case
fails. The package: cases.py (the cases, in table order), runner.py (the registry, the context a
case runs in, the checks every run passes), report.py (the table); this file runs them.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

from tests.stress import cases  # noqa: F401 - registers the cases
from tests.stress.report import write_table
from tests.stress.runner import CASES, Ctx, Failure


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--hardsphere", required=True)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--table")
    ap.add_argument("--only", nargs="*")
    a = ap.parse_args()
    results, failed = [], 0
    for c in CASES:
        if a.only and c.name not in a.only and c.fn.__name__ not in a.only:
            continue
        if a.quick and not c.quick:
            continue
        with tempfile.TemporaryDirectory() as work:
            ctx = Ctx(os.path.abspath(a.hardsphere), work, full=not a.quick)
            t0 = time.time()
            try:
                c.fn(ctx)
                ok, why = True, ""
            except (Failure, subprocess.TimeoutExpired) as e:
                ok, why = False, str(e)
            results.append((c, ok, why, time.time() - t0, ctx.rows))
        failed += not ok
        print(f"{'PASS' if ok else 'FAIL'} {c.name} ({results[-1][3]:.1f} s){': ' + why if why else ''}", flush=True)
    if a.table:
        write_table(a.table, results, quick=a.quick)
    print(f"{len(results) - failed} of {len(results)} cases passed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
