#!/usr/bin/env python3
"""The seed paper's figures 1-3 (space partitioning) from the standalone stepper.

  python3 -m compare.seed_figures --out DIR [--quick] [--build DIR] [--hardsphere PATH]
  python3 -m compare.seed_figures --out DIR --from-json   (the figures and seed_figures.md again from
                                                           DIR/seed_figures.json, no runs)

Fig. 1: the ideal number of boxes (the cubic cell grid K^3 with the least time per step, from a
scan of K per axis) against N; fig. 2: time per step against N with that grid (linear); fig. 3:
time per step with one box (`--cells 1`, all pairs, quadratic). Writes into DIR
seed_fig1_ideal_boxes.png, seed_fig2_linear.png, seed_fig3_one_box.png, seed_figures.json and
seed_figures.md. Time per step = loop CPU time (`loop_cpu_seconds`, stepping loop only, set-up
excluded, as in the paper) / steps, median of R runs; the runs of one N are interleaved over K
(round r runs every K once) so a slow spell of the shared machine hits all K alike.

The paper keeps the world fixed (50^3, radius 0.5), so its density grows with N; here the
packing fraction is fixed instead (default 0.1; the 50^3 world holds ~24000 spheres at 0.1) so
that N can span 1000 to 256000 spheres at one density. Speed is reported, never asserted.
`run(hardsphere, out_dir, quick, progress=print)` is the importable entry point.
"""
import json
import math
import os
import statistics
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from compare import harness  # noqa: E402
from compare.machine_info import cpu_model  # noqa: E402

# Spheres per cell the K scan aims at: 8 down to ~0.35 in steps of sqrt(2) (~12% in K).
FULL = dict(n_ideal=[1000 * 2 ** k for k in range(9)], n_one=[500, 1000, 2000, 4000],
            per_cell=[8 * 2 ** (-j / 2) for j in range(10)], repeats=3, target=0.25)
QUICK = dict(n_ideal=[1000, 4000, 16000], n_one=[500, 1000, 2000, 4000],
             per_cell=[4, 2, 1, 0.5], repeats=3, target=0.06)
NEAR = 1.10  # K whose median time is within 10% of the best count as "near-ideal" (fig. 1 bars)


class Refused(Exception):
    """The program refused the cell grid (exit status 2: cells narrower than a diameter)."""


def hs_run(hardsphere, n, phi, dt, steps, cells):
    cmd = [hardsphere, "run", "--n", str(n), "--phi", repr(phi), "--dt", repr(dt), "--steps", str(steps),
           "--cells", str(cells), "--json", "-"]
    p = harness.run_program(cmd, expect=None)
    if p.returncode == 2:
        raise Refused(p.stderr.strip().splitlines()[-1] if p.stderr.strip() else "exit status 2")
    if p.returncode != 0:
        raise harness.ProgramError(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()}")
    j = json.loads(p.stdout)
    assert j["n"] == n and j["steps"] == steps, (j["n"], j["steps"])
    return j


def fit_loglog(x, y):
    """Least squares of log y on log x: slope, its standard error, intercept (natural logs)."""
    lx, ly = np.log(np.asarray(x, float)), np.log(np.asarray(y, float))
    if len(lx) < 2:
        return float("nan"), float("nan"), float("nan")
    a = np.vstack([lx, np.ones_like(lx)]).T
    (slope, icept), *_ = np.linalg.lstsq(a, ly, rcond=None)
    if len(lx) > 2:
        resid = ly - (slope * lx + icept)
        se = math.sqrt(float(resid @ resid) / (len(lx) - 2) / float(((lx - lx.mean()) ** 2).sum()))
    else:
        se = float("nan")
    return float(slope), se, float(icept)


def fmt_time(s):
    return f"{s * 1e3:.3g} ms" if s >= 1e-3 else f"{s * 1e6:.3g} µs"


def scan_ideal(hardsphere, n, phi, dt, cfg, progress, box_len):
    """Median time per step for each K of the scan at this N; returns the N's record."""
    # Calibration (and warm-up) run at ~1 sphere per cell: sets the steps of the scan's runs.
    k1 = max(1, round(n ** (1 / 3)))
    while k1 > 1 and box_len / k1 <= 1.0:
        k1 -= 1
    cal_steps = max(10, int(2e6 / n))
    j = hs_run(hardsphere, n, phi, dt, cal_steps, k1)
    per_step = j["loop_cpu_seconds"] / cal_steps
    steps = max(30, math.ceil(cfg["target"] / max(per_step, 1e-9)))
    progress(f"seed fig: N={n} calibrate cells {k1}^3: {fmt_time(per_step)}/step -> {steps} steps/run")
    ks = sorted({max(1, round((n / x) ** (1 / 3))) for x in cfg["per_cell"]})
    times = {k: [] for k in ks}
    refused = {}
    for r in range(cfg["repeats"]):
        for k in ks:
            if k in refused:
                continue
            try:
                j = hs_run(hardsphere, n, phi, dt, steps, k)
            except Refused as e:
                refused[k] = str(e)
                progress(f"seed fig: N={n} cells {k}^3 refused (exit 2), skipped")
                continue
            t = j["loop_cpu_seconds"] / steps
            times[k].append(t)
            progress(f"seed fig: N={n} cells {k}^3 ({n / k ** 3:.2g}/cell) {steps} steps: "
                     f"{fmt_time(t)}/step [{r + 1}/{cfg['repeats']}]")
    scan = [{"k": k, "cells": k ** 3, "spheres_per_cell": n / k ** 3, "steps": steps,
             "seconds_per_step": times[k], "seconds_per_step_median": statistics.median(times[k])}
            for k in ks if times[k]]
    if not scan:
        raise harness.ProgramError(f"every cell grid refused at N={n}: {refused}")
    best = min(scan, key=lambda s: s["seconds_per_step_median"])
    near = [s["k"] for s in scan if s["seconds_per_step_median"] <= NEAR * best["seconds_per_step_median"]]
    return {"n": n, "box_length": box_len, "k": best["k"], "cells": best["cells"],
            "spheres_per_cell": n / best["cells"], "seconds_per_step_median": best["seconds_per_step_median"],
            "seconds_per_step": best["seconds_per_step"], "steps": steps, "repeats": cfg["repeats"],
            "near_ideal_k": [min(near), max(near)], "scan": scan,
            "refused": [{"k": k, "message": m} for k, m in sorted(refused.items())]}


def scan_one_box(hardsphere, ns, phi, dt, cfg, progress):
    out = []
    pred = None  # predicted seconds per step from the previous N, scaled by N^2
    for i, n in enumerate(ns):
        if pred is None:
            j = hs_run(hardsphere, n, phi, dt, 20, 1)
            pred = j["loop_cpu_seconds"] / 20
            progress(f"seed fig: N={n} one box calibrate: {fmt_time(pred)}/step")
        steps = max(3, math.ceil(cfg["target"] / max(pred, 1e-9)))
        ts = []
        for r in range(cfg["repeats"]):
            j = hs_run(hardsphere, n, phi, dt, steps, 1)
            ts.append(j["loop_cpu_seconds"] / steps)
            progress(f"seed fig: N={n} one box {steps} steps: {fmt_time(ts[-1])}/step [{r + 1}/{cfg['repeats']}]")
        med = statistics.median(ts)
        out.append({"n": n, "k": 1, "cells": 1, "steps": steps, "repeats": cfg["repeats"],
                    "seconds_per_step": ts, "seconds_per_step_median": med})
        if i + 1 < len(ns):
            pred = med * (ns[i + 1] / n) ** 2
    return out


def guide(ax, xs, slope, x0, y0, label):
    xs = np.array([min(xs), max(xs)], float)
    ax.plot(xs, y0 * (xs / x0) ** slope, "k--", lw=1, alpha=0.6, label=label)


def err_bars(recs):
    med = np.array([r["seconds_per_step_median"] for r in recs])
    lo = med - np.array([min(r["seconds_per_step"]) for r in recs])
    hi = np.array([max(r["seconds_per_step"]) for r in recs]) - med
    return med, np.vstack([lo, hi])


def plot(out, ideal, one, fits, phi, dt):
    title = f"hardsphere stepper, φ = {phi:g}, dt = {dt:g}"
    ns = np.array([r["n"] for r in ideal], float)

    fig, ax = plt.subplots(figsize=(6, 4.5))
    cells = np.array([r["cells"] for r in ideal], float)
    lo = cells - np.array([r["near_ideal_k"][0] ** 3 for r in ideal])
    hi = np.array([r["near_ideal_k"][1] ** 3 for r in ideal]) - cells
    ax.errorbar(ns, cells, yerr=np.vstack([np.maximum(lo, 0), np.maximum(hi, 0)]), fmt="o", capsize=3,
                label=f"fastest K³ (bars: within {round((NEAR - 1) * 100)}% of it)")
    x = fits["spheres_per_box"]
    guide(ax, ns, 1, 1.0, 1 / x, f"slope 1: N / {x:.2g} spheres per box")
    f = fits["ideal_boxes"]
    ax.plot([], [], " ", label=f"fitted slope {f['slope']:.2f} ± {f['se']:.2f}")
    ax.set(xscale="log", yscale="log", xlabel="number of spheres N", ylabel="ideal number of boxes",
           title="Fig. 1: ideal number of boxes\n" + title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "seed_fig1_ideal_boxes.png", dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6, 4.5))
    med, bars = err_bars(ideal)
    f = fits["ideal"]
    ax.errorbar(ns, med, yerr=bars, fmt="o", capsize=3, label=f"ideal boxes: slope {f['slope']:.2f} ± {f['se']:.2f}")
    ax.plot(ns, np.exp(f["intercept"]) * ns ** f["slope"], "-", lw=1, color="C0", alpha=0.6)
    guide(ax, ns, 1, ns[0], med[0], "slope 1")
    ax.set(xscale="log", yscale="log", xlabel="number of spheres N", ylabel="CPU time per step [s]",
           title="Fig. 2: linear complexity with the ideal number of boxes\n" + title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "seed_fig2_linear.png", dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6, 4.5))
    n1 = np.array([r["n"] for r in one], float)
    med1, bars1 = err_bars(one)
    f = fits["one_box"]
    ax.errorbar(n1, med1, yerr=bars1, fmt="s", color="C3", capsize=3,
                label=f"one box: slope {f['slope']:.2f} ± {f['se']:.2f}")
    ax.plot(n1, np.exp(f["intercept"]) * n1 ** f["slope"], "-", lw=1, color="C3", alpha=0.6)
    guide(ax, n1, 2, n1[-1], med1[-1], "slope 2")
    sel = [r for r in ideal if r["n"] <= n1.max() * 1.01]
    if sel:
        ax.plot([r["n"] for r in sel], [r["seconds_per_step_median"] for r in sel], "o", color="0.6",
                label="ideal boxes (fig. 2), for comparison")
    ax.set(xscale="log", yscale="log", xlabel="number of spheres N", ylabel="CPU time per step [s]",
           title="Fig. 3: quadratic complexity with one box\n" + title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "seed_fig3_one_box.png", dpi=120)
    plt.close(fig)


def markdown(res):
    fits, ideal, one = res["fits"], res["ideal"], res["one_box"]
    by_n = {}
    for r in ideal:
        by_n.setdefault(r["n"], {})["ideal"] = r
    for r in one:
        by_n.setdefault(r["n"], {})["one"] = r
    reps = sorted({r["repeats"] for r in ideal + one})
    lines = [
        "### Seed paper figures 1-3: space partitioning",
        "",
        f"Standalone stepper (`hardsphere run`), packing fraction φ = {res['phi']:g} (fixed; the paper fixes "
        f"the world at 50³ with radius 0.5 instead, so its density grows with N), radius 0.5, dt = {res['dt']:g}, "
        f"default random initial state and seed. Time per step = median of {'/'.join(map(str, reps))} runs of the "
        f"stepping loop's CPU time (`loop_cpu_seconds`, set-up excluded) / steps, steps chosen for "
        f"≥ ~{res['target_seconds']:g} s of loop time per run. The ideal number of boxes is the cubic grid K³ with "
        f"the least median time in a scan of K per axis (~{min(res['per_cell']):.2g} to {max(res['per_cell']):.2g} "
        f"spheres per box); the runs of one N are interleaved over K. Machine: {res['machine']['cpu']}, "
        f"{res['machine']['cores']} cores, shared (timing noise ±20-40% per run). Unlike the paper's boxes, this "
        f"stepper's cells also set its pair list's skin (cell width − diameter): fewer, wider cells mean longer "
        f"lists rebuilt less often, and one box lists all pairs once and checks them every step.",
        "",
        "| N | ideal boxes (K³) | spheres per box | near-ideal K | time/step, ideal boxes | time/step, one box |",
        "|---:|---:|---:|---:|---:|---:|",
    ]
    for n in sorted(by_n):
        i, o = by_n[n].get("ideal"), by_n[n].get("one")
        cols = [f"{n}"]
        if i:
            a, b = i["near_ideal_k"]
            cols += [f"{i['k']}³ = {i['cells']}", f"{i['spheres_per_cell']:.2f}", f"{a}-{b}" if a != b else f"{a}",
                     fmt_time(i["seconds_per_step_median"])]
        else:
            cols += ["—"] * 4
        cols.append(fmt_time(o["seconds_per_step_median"]) if o else "—")
        lines.append("| " + " | ".join(cols) + " |")
    fi, fo, fb = fits["ideal"], fits["one_box"], fits["ideal_boxes"]
    refused = sum(len(r["refused"]) for r in ideal)
    lines += [
        "",
        f"Fitted slopes (least squares in log-log, ± standard error): time per step with the ideal boxes "
        f"**{fi['slope']:.2f} ± {fi['se']:.2f}** (paper: linear, 1); with one box **{fo['slope']:.2f} ± "
        f"{fo['se']:.2f}** (paper: quadratic, 2); ideal number of boxes against N {fb['slope']:.2f} ± "
        f"{fb['se']:.2f} (1 = a fixed number of spheres per box), {fits['spheres_per_box']:.2f} spheres per "
        f"box (geometric mean). Near-ideal K: grids within {round((NEAR - 1) * 100)}% of the fastest (a flat "
        f"optimum)." + (f" {refused} grid(s) refused by `--cells` (cells narrower than a diameter) were skipped."
                        if refused else ""),
        "",
        "![Fig. 1: ideal number of boxes](seed_fig1_ideal_boxes.png)",
        "![Fig. 2: time per step with the ideal number of boxes](seed_fig2_linear.png)",
        "![Fig. 3: time per step with one box](seed_fig3_one_box.png)",
        "",
    ]
    return "\n".join(lines)


def run(hardsphere, out_dir, quick, progress=print, phi=0.1, dt=0.01):
    """Measures, plots and writes the five files into out_dir; returns the JSON record."""
    cfg = QUICK if quick else FULL
    hardsphere = str(Path(hardsphere).resolve())
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.monotonic()
    ideal = []
    for n in cfg["n_ideal"]:
        box_len = (n * math.pi / 6 / phi) ** (1 / 3)
        ideal.append(scan_ideal(hardsphere, n, phi, dt, cfg, progress, box_len))
    one = scan_one_box(hardsphere, cfg["n_one"], phi, dt, cfg, progress)
    ns = [r["n"] for r in ideal]
    s_i, e_i, c_i = fit_loglog(ns, [r["seconds_per_step_median"] for r in ideal])
    s_o, e_o, c_o = fit_loglog([r["n"] for r in one], [r["seconds_per_step_median"] for r in one])
    s_b, e_b, c_b = fit_loglog(ns, [r["cells"] for r in ideal])
    spb = math.exp(statistics.fmean(math.log(r["spheres_per_cell"]) for r in ideal))
    res = {
        "phi": phi, "dt": dt, "radius": 0.5, "quick": bool(quick), "program": hardsphere,
        "per_cell": cfg["per_cell"], "target_seconds": cfg["target"],
        "timing": "median over repeats of loop_cpu_seconds / steps (stepping loop CPU time)",
        "machine": {"cpu": cpu_model(), "cores": len(os.sched_getaffinity(0))},
        "fits": {"ideal": {"slope": s_i, "se": e_i, "intercept": c_i},
                 "one_box": {"slope": s_o, "se": e_o, "intercept": c_o},
                 "ideal_boxes": {"slope": s_b, "se": e_b, "intercept": c_b},
                 "spheres_per_box": spb},
        "ideal": ideal, "one_box": one,
    }
    plot(out, ideal, one, res["fits"], phi, dt)
    res["runtime_seconds"] = time.monotonic() - t0
    (out / "seed_figures.json").write_text(json.dumps(res, indent=1) + "\n")
    (out / "seed_figures.md").write_text(markdown(res))
    progress(f"seed fig: slopes ideal {s_i:.2f}±{e_i:.2f}, one box {s_o:.2f}±{e_o:.2f}, boxes {s_b:.2f}; "
             f"{spb:.2f} spheres/box; {res['runtime_seconds']:.0f} s")
    return res


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",))
    ap.add_argument("--quick", action="store_true", help="3 N values, short runs (~20 s)")
    ap.add_argument("--phi", type=float, default=0.1, help="packing fraction (default 0.1)")
    ap.add_argument("--dt", type=float, default=0.01, help="time step (default 0.01)")
    ap.add_argument("--from-json", action="store_true", help="no runs: figures and markdown from DIR/seed_figures.json")
    a = ap.parse_args(argv)
    session = harness.Session("compare.seed_figures", a, argv)
    out = session.out()
    if a.from_json:
        res = json.loads((out / "seed_figures.json").read_text())
        plot(out, res["ideal"], res["one_box"], res["fits"], res["phi"], res["dt"])
        (out / "seed_figures.md").write_text(markdown(res))
        return session.finish([], out / "seed_figures.md")
    hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
    run(hs, out, a.quick, progress=session.log, phi=a.phi, dt=a.dt)
    return session.finish([], out / "seed_figures.md")


if __name__ == "__main__":
    harness.main(main)
