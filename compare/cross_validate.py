#!/usr/bin/env python3
"""Cross-validation: the same states through every engine, distributions and timings compared.

  python3 -m compare.cross_validate [--quick] --out DIR [--build DIR] [--hardsphere PATH] [--lmp-hs PATH]
      [--work DIR [--resume]]

Engines: the standalone stepper (double, float; a dt sweep with the default dt 0.01), the event
engine, lmp_hs + fix hardsphere (serial, 2 ranks), Debian's LAMMPS with elastic gran/hooke and
gran/hertz/history and LIGGGHTS's hertz model, over a stiffness sweep. Writes DIR/cross_validation.md
with figures and DIR/cross_validation.json (and the seed paper's figures, compare.seed_figures);
exits 1 when an engine disagrees beyond the stated tolerances (docs/reports/validation/
cross_validation.md lists them). --quick: one small state, minutes. The states and runs go to --work
(kept there; --resume skips the runs an earlier call with that --work finished).
"""
import json
import pickle
import shutil
import time

from compare import harness, seed_figures
from compare.crossval import plan as xv_plan
from compare.crossval.analysis import analyse, check_agreement
from compare.crossval.engines import Engines
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
        print(f"[{elapsed:7.0f} s] {text} (~{left:.0f} s left)", flush=True)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere", "lmp_hs"), work=True)
    ap.add_argument("--quick", action="store_true", help="one small state, a few minutes")
    ap.add_argument("--resume", action="store_true", help="keep the runs finished by an earlier call with this --work")
    ap.add_argument("--no-seed-figures", action="store_true", help="skip the seed paper's scaling figures")
    a = ap.parse_args(argv)
    if a.resume and not a.work:
        raise harness.InputError("--resume needs the --work directory of the earlier call")
    session = harness.Session("compare.cross_validate", a, argv)
    tools = harness.tools(a, need=("hardsphere", "lmp_hs", "lmp", "liggghts", "mpirun"))
    out = session.out()
    engines = Engines(tools["hardsphere"], tools["lmp_hs"], tools["lmp"], tools["liggghts"], tools["mpirun"])
    plan = xv_plan.quick_plan() if a.quick else xv_plan.full_plan()
    progress = Progress(sum(t.cost for t in plan.tasks) + plan.seed_figure_cost * (not a.no_seed_figures))
    with session.workdir() as work:
        runs_dir = work / "runs"
        rows, curves = [], {}
        done_file = work / "runs_done.pickle"  # results so far: --resume skips them
        if a.resume and done_file.exists():
            rows, curves = pickle.loads(done_file.read_bytes())
        done = {(r["state"], r["setting"]) for r in rows}
        for state in plan.states:
            state.path = make_state(tools["hardsphere"], tools["lmp"], work / "states", state.n, state.phi,
                                    state.composition, state.equilibrate, log=lambda s: progress(0, s))
        for task in plan.tasks:
            if (task.state.label, task.label) in done:
                progress(task.cost, f"{task.state.label}: {task.label}: done before")
                continue
            run_dir = runs_dir / task.state.label / task.label.replace(" ", "_").replace(",", "").replace("=", "")
            result = task.execute(engines, run_dir)
            row, curve = analyse(task, result, rows)
            rows.append(row)
            curves[(task.state.label, task.label)] = curve
            progress(task.cost, f"{task.state.label}: {task.label}: Z {row['Z']:.4f} +- {row['Z_err']:.4f}"
                     + (f" (mapped {row['Z_mapped']:.4f})" if row.get("Z_mapped") is not None else "")
                     + f", {row['cpu_seconds_per_tau']:.3g} CPU s/tau")
            done_file.write_bytes(pickle.dumps((rows, curves)))
            if not a.work:
                shutil.rmtree(run_dir, ignore_errors=True)
    seed = None
    if not a.no_seed_figures:
        seed = seed_figures.run(tools["hardsphere"], str(out), a.quick,
                                progress=lambda s: progress(plan.seed_figure_cost / (60 if a.quick else 300), s))
    failures = check_agreement(rows, plan)
    (out / "cross_validation.json").write_text(json.dumps(
        {"plan": plan.describe(), "tolerances": plan.tolerances, "failures": failures, "results": rows},
        indent=1, default=float) + "\n")
    report = write_report(out, plan, rows, curves, failures, tools, seed)
    return session.finish(failures, report)


if __name__ == "__main__":
    harness.main(main)
