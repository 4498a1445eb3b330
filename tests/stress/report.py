"""The stress suite's report: docs/reports/stress.md (every case, its criterion and the worst
figures over its runs) and stress.json beside it."""
import json
from pathlib import Path

from compare.machine_info import cpu_model
from tests.stress.runner import momentum_drift, nan_count


def write_table(path, results, quick):
    """docs/reports/stress.md: every case, its criterion and the worst figures over its runs."""
    total = sum(r[3] for r in results)
    lines = [
        "# Stress suite",
        "",
        "Hard cases for both engines (`tests/stress/stress.py`), each with a pass criterion. Every run must also keep "
        "energy (relative drift below 1e-12 in double, 1e-4 in float unless stated) and momentum (periodic boxes), "
        "end without an overlap beyond the rounding tolerance (`overlap_tolerance`) and without NaN. ctest runs the "
        "quick subset (label `stress`); this table is the " + ("quick" if quick else "full") + " set:",
        "",
        "```sh",
        "/usr/bin/python3 -m tests.stress.stress --hardsphere build/standalone/hardsphere" + (" --quick" if quick else "") +
        " --table docs/reports/stress.md",
        "```",
        "",
        f"{len(results)} cases, {total:.0f} s in all on one core of a {cpu_model()}. Columns: simulated runs, "
        "then the worst over them of the relative energy drift, the momentum drift |p1 - p0| / sum m|v|, the "
        "largest overlap (diameters are 1 unless stated) and the NaN count, and the wall time of the case.",
        "",
        "| case | pass criterion | simulated runs | energy drift | momentum drift | max overlap | NaN | time (s) | result |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    cases = []
    for c, ok, why, secs, rows in results:
        case = dict(name=c.name, criterion=c.criterion, runs=len(rows), seconds=secs, **{"pass": ok, "why": why})
        if rows:
            e = max(abs(j["energy_rel_drift"]) for j in rows)
            p = max((momentum_drift(j) for j in rows if "w" not in j["box"]["boundary"]), default=0.0)
            o = max(j["max_overlap"] for j in rows)
            nans = sum(nan_count(j) for j in rows)
            figures = f"{e:.1e} | {p:.1e} | {o:.1e} | {nans}"
            case.update(energy_drift=e, momentum_drift=p, max_overlap=o, nan=nans)
        else:  # refusals and generator cases: no simulated state to measure
            figures = "- | - | - | -"
        lines.append(f"| {c.name} | {c.criterion} | {len(rows)} | {figures} | {secs:.1f} | "
                     f"{'pass' if ok else 'FAIL: ' + why} |")
        cases.append(case)
    Path(path).write_text("\n".join(lines) + "\n")
    Path(path).with_suffix(".json").write_text(json.dumps(dict(quick=quick, seconds=total, cpu=cpu_model(), cases=cases),
                                                          indent=1) + "\n")
