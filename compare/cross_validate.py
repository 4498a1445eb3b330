#!/usr/bin/env python3
"""Cross-validation: the same states through every engine, distributions and timings compared.

  python3 -m compare.cross_validate [--quick] [--build BUILD_DIR] --out DIR

Engines: the standalone stepper (double, float; a dt sweep with the default dt 0.01), the event
engine, lmp_hs + fix hardsphere (serial, 2 ranks), Debian's LAMMPS with elastic gran/hooke and
gran/hertz/history and LIGGGHTS's hertz model, over a stiffness sweep. Writes DIR/report.md with
figures and DIR/cross_validation.json; exits 1 when an engine disagrees beyond the stated
tolerances (docs/reports/validation/cross_validation.md lists them). --quick: one small state, minutes.
"""
import argparse
import json
import pickle
import shutil
import sys
import time
from pathlib import Path

from compare import seed_figures
from compare.crossval import plan as xv_plan
from compare.crossval.analysis import analyse, check_agreement
from compare.crossval.engines import ROOT, Engines, find_tools
from compare.crossval.report import write_report
from compare.crossval.states import make_state


class Progress:
    """One line per run: elapsed time and the remaining time estimated from the plan's costs."""

    def __init__(self, total_cost):
        self.t0, self.total, self.done = time.time(), total_cost, 0.0

    def __call__(self, cost, text):
        self.done += cost
        elapsed = time.time() - self.t0
        left = elapsed / self.done * (self.total - self.done) if self.done > 0 else float("nan")
        print(f"[{elapsed:7.0f} s elapsed, ~{left:5.0f} s left] {text}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="one small state, a few minutes")
    ap.add_argument("--build", default=str(ROOT / "build"), help="build directory (default: build)")
    ap.add_argument("--out", required=True, help="output directory (report.md, cross_validation.json, figures)")
    ap.add_argument("--keep", action="store_true", help="keep the runs' trajectories (DIR/runs)")
    ap.add_argument("--resume", action="store_true", help="keep the runs finished by an earlier call with this --out")
    ap.add_argument("--no-seed-figures", action="store_true", help="skip the seed paper's scaling figures")
    a = ap.parse_args(argv)
    out = Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    tools = find_tools(a.build)
    missing = [k for k in ("lmp_hs", "lmp", "liggghts", "mpirun") if not tools[k]]
    if missing:
        sys.exit(f"cross_validate: missing {', '.join(missing)} (scripts/setup.sh installs and builds them)")
    engines = Engines(str(tools["hardsphere"]), str(tools["lmp_hs"]), tools["lmp"], tools["liggghts"],
                      tools["mpirun"])
    plan = xv_plan.quick_plan() if a.quick else xv_plan.full_plan()
    runs_dir = out / "runs"
    progress = Progress(sum(t.cost for t in plan.tasks) + plan.seed_figure_cost * (not a.no_seed_figures))
    rows, curves = [], {}
    done_file = out / "runs_done.pickle"  # results so far: --resume skips them
    if a.resume and done_file.exists():
        rows, curves = pickle.loads(done_file.read_bytes())
    done = {(r["state"], r["setting"]) for r in rows}
    for state in plan.states:
        path = make_state(tools["hardsphere"], tools["lmp"], out / "states", state.n, state.phi, state.composition,
                          state.equilibrate, log=lambda s: progress(0, s))
        state.path = path
    for task in plan.tasks:
        if (task.state.label, task.label) in done:
            progress(task.cost, f"{task.state.label}: {task.label}: done before")
            continue
        work = runs_dir / task.state.label / task.label.replace(" ", "_").replace(",", "").replace("=", "")
        run = task.execute(engines, work)
        row, curve = analyse(task, run, rows)
        rows.append(row)
        curves[(task.state.label, task.label)] = curve
        progress(task.cost, f"{task.state.label}: {task.label}: Z {row['Z']:.4f} +- {row['Z_err']:.4f}"
                 + (f" (mapped {row['Z_mapped']:.4f})" if row.get("Z_mapped") is not None else "")
                 + f", {row['cpu_seconds_per_tau']:.3g} CPU s/tau")
        done_file.write_bytes(pickle.dumps((rows, curves)))
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    seed = None
    if not a.no_seed_figures:
        seed = seed_figures.run(str(tools["hardsphere"]), str(out), a.quick,
                                progress=lambda s: progress(plan.seed_figure_cost / (60 if a.quick else 300), s))
    failures = check_agreement(rows, plan)
    (out / "cross_validation.json").write_text(json.dumps(
        {"plan": plan.describe(), "tolerances": plan.tolerances, "failures": failures, "results": rows},
        indent=1, default=float) + "\n")
    write_report(out, plan, rows, curves, failures, tools, seed)
    if not a.keep:
        shutil.rmtree(runs_dir, ignore_errors=True)
    done_file.unlink()
    print(f"cross_validate: {len(rows)} runs, {len(failures)} disagreements; report in {out / 'report.md'}")
    for f in failures:
        print("  DISAGREE: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
