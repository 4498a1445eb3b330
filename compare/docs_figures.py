#!/usr/bin/python3
"""README/documentation figures redrawn from committed data (no simulation is run).

  pareto_time_error.png      Run time against pressure error, one panel per packing fraction: every
                             stepper setting (dt, float/double, overlap/sweep detection) of
                             docs/reports/event_engine/accuracy.json as faint points, their Pareto front (the
                             cheapest setting with |Z/Z_event - 1| <= x) as a staircase, the exact event
                             engine as a horizontal line (star: its own 1-sigma statistical error), the
                             band where an error is indistinguishable from noise (< 2 sigma of one run),
                             and, where N and phi match (N = 8000), the soft-sphere peers (LAMMPS
                             gran/hooke, gran/hertz/history, LIGGGHTS hertz; raw and Barker-Henderson
                             mapped Z) and the stepper of that same run from
                             docs/reports/validation/cross_validation.json. Each panel also quotes the report's CPU
                             ratios at matched (1%) accuracy, computed by compare.crossval.report.timing_rows.
  eos_kolafa.png             (Z - Z_Kolafa)/Z_Kolafa against phi: event engine (docs/reports/event_engine/eos.json,
                             N = 4000), and the event engine's long reference runs, the stepper (dt = 0.01,
                             double and float) and lmp_hs from cross_validation.json (monodisperse states,
                             N = 8000 and 64000); Carnahan-Starling's residual as a line.
  collisions_per_second.png  Collisions per CPU second against N, one colour per phi: event engine from
                             docs/reports/event_engine/speed.json, eos.json, accuracy.json and
                             cross_validation.json; stepper (dt = 0.01) from accuracy.json and
                             cross_validation.json. Collisions per unit time = rate * N / 2 (the rate
                             counts each collision for both spheres: compare.accuracy's eos run length
                             t = collisions / (N rate / 2)).

Usage: /usr/bin/python3 -m compare.docs_figures [--out DIR]   (default: docs/reports/figures)
"""
import json
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.lines  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from compare.hard_sphere_theory import z_carnahan_starling as z_cs, z_kolafa  # noqa: E402
from compare import harness  # noqa: E402
from compare.crossval.report import ENGINE_NAMES, timing_rows  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

ACCURACY = ROOT / "docs/reports/event_engine/accuracy.json"
EOS = ROOT / "docs/reports/event_engine/eos.json"
SPEED = ROOT / "docs/reports/event_engine/speed.json"
XV = ROOT / "docs/reports/validation/cross_validation.json"
MACHINE = ("Timings: 2-core AMD EPYC VM (shared; single runs vary by 20-40%), one thread, "
           "CPU time of the step/event loop.")
FLOOR = 1e-5  # smaller |errors| (double-precision stepper on the event engine's own trajectory) drawn here
SOFT = ("lammps hooke", "lammps hertz", "liggghts hertz")
PHI_COLOUR = {0.1: "C0", 0.2: "C1", 0.3: "C2", 0.35: "C4", 0.4: "C5", 0.45: "C3"}


def load(path):
    return json.loads(Path(path).read_text())


def xv_rows(state=None, **match):
    rows = load(XV)["results"]
    return [r for r in rows if (state is None or r["state"] == state) and all(r[k] == v for k, v in match.items())]


def pareto_front(points):
    """Lower-left staircase of (error, cost) points: sorted by error, each cheaper than all with smaller error."""
    front, best = [], math.inf
    for err, cost in sorted(points):
        if cost < best:
            front.append((err, cost))
            best = cost
    return front


def accuracy_panels(rows):
    """(phi, N) per panel: N = 8000 where accuracy.json has it (the peers' N), else its largest N."""
    out = []
    for phi in sorted({r["phi"] for r in rows}):
        ns = {r["n"] for r in rows if r["phi"] == phi}
        out.append((phi, 8000 if 8000 in ns else max(ns)))
    return out


def cheapest_within(front, tol=0.01):
    ok = [p for p in front if p[0] <= tol]
    return min(ok, key=lambda p: p[1]) if ok else None


def peer_ratios(state):
    """The committed report's CPU ratios at matched accuracy (soft engines, one rank), as text lines."""
    lines = []
    for name, _, cpu, _, cpu_m, ratio, ratio_m in timing_rows(xv_rows(), state):
        if name in (ENGINE_NAMES[e] for e in SOFT):
            lines.append(f"{name}: " + ", ".join(f"{v}x {tag}" if v != "-" else f"none within 1% {tag}"
                                                 for v, tag in ((ratio, "raw"), (ratio_m, "mapped"))))
    return lines


def draw_peers(ax, state, z_ref):
    """Soft engines' sweeps (raw and mapped Z) and the same run's stepper; same N and phi as the panel."""
    for engine, colour, marker in zip(SOFT, ("C1", "C2", "C4"), "osD"):
        s = sorted(xv_rows(state, engine=engine, ranks=1, steps_per_contact=20), key=lambda r: r["bh_shift"])
        cpu = [r["cpu_seconds_per_tau"] for r in s]
        for key, ls, fill, tag in (("Z", "--", "none", "raw"), ("Z_mapped", "-", colour, "BH-mapped")):
            err = [max(abs(r[key] / z_ref - 1), FLOOR) for r in s]
            ax.plot(err, cpu, ls=ls, marker=marker, color=colour, mfc=fill, ms=4, lw=0.9,
                    label=f"{ENGINE_NAMES[engine]}, {tag} Z (stiffness sweep)")
    st = xv_rows(state, engine="stepper")
    ax.plot([max(abs(r["Z"] / z_ref - 1), FLOOR) for r in st], [r["cpu_seconds_per_tau"] for r in st], "x",
            color="0.35", ms=5, label="stepper in the peers' run (cross_validation.json)")


def fig_pareto(out):
    acc = load(ACCURACY)
    panels = accuracy_panels(acc)
    fig, axes = plt.subplots(1, len(panels), figsize=(5.4 * len(panels), 6.2), squeeze=False)
    summary, fronts = [], {}
    for ax, (phi, n) in zip(axes[0], panels):
        sub = [r for r in acc if r["phi"] == phi and r["n"] == n]
        ev = next(r for r in sub if r["engine"] == "event")
        pts = [(abs(r["z_rel_err"]), r["cpu_per_time"]) for r in sub if r["engine"] == "stepper"]
        front = fronts[(phi, n)] = pareto_front(pts)
        noise = 2 * ev["z_ref_err"] / ev["z_ref"]
        ax.axvspan(FLOOR / 2, noise, color="0.88", lw=0, label="|error| < 2σ of one run (noise)")
        ax.axvline(0.01, color="0.5", ls=":", lw=1, label="1% error")
        ax.plot([max(p[0], FLOOR) for p in pts], [p[1] for p in pts], "o", color="C0", alpha=0.3, ms=4,
                label=f"stepper, every setting (accuracy.json; |error| < {FLOOR:g} drawn at {FLOOR:g})")
        fx = [max(p[0], FLOOR) for p in front] + [1.0]
        ax.plot(fx, [p[1] for p in front] + [front[-1][1]], "-", color="C0", lw=2, drawstyle="steps-post",
                label="stepper Pareto front (cheapest with |error| ≤ x)")
        ax.axhline(ev["cpu_per_time"], color="k", lw=1.5, label="event engine (exact)")
        ax.plot([ev["z_err"] / ev["z"]], [ev["cpu_per_time"]], "k*", ms=12, label="event engine at its 1σ error")
        state = f"mono_n8000_phi{phi:g}"
        on_axes = n == 8000 and xv_rows(state)
        if on_axes:
            draw_peers(ax, state, xv_rows(state, reference=True)[0]["Z"])
        ratios = peer_ratios(state) if xv_rows(state) else []
        if ratios:
            head = "cross_validation.md, CPU time at 1% accuracy over the stepper's (double)" + (
                "" if on_axes else ",\nN = 8000 (peers not drawn: this panel is N = 10000)") + ":\n"
            ax.text(0.0, -0.19, head + "\n".join(ratios), transform=ax.transAxes, ha="left", va="top",
                    fontsize=7, bbox=dict(fc="0.97", ec="0.7"))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(FLOOR / 2, 0.5)
        ax.set_xlabel("relative pressure error |Z / Z_event − 1|")
        ax.set_ylabel("CPU s per unit simulated time σ√(m/kT)")
        ax.set_title(f"N = {n}, φ = {phi:g}" + ("  (stepper and peers)" if on_axes else "  (stepper only)"))
        best = cheapest_within(front)
        b = next(r for r in sub if r["engine"] == "stepper" and r["cpu_per_time"] == best[1])
        summary.append(f"pareto: phi {phi:g} (N = {n}): stepper at <= 1% error costs {best[1]:.4g} CPU s per unit time "
                       f"({b['precision']} {b['detect']} dt {b['dt']:g}, |error| {100 * best[0]:.2f}%, noise 2 sigma = "
                       f"{100 * noise:.2f}%), event engine {ev['cpu_per_time']:.4g}; front: {len(front)} of {len(pts)} "
                       "settings" + (f"; report's ratios at N = 8000: {'; '.join(ratios)}" if ratios else ""))
    handles, labels = [], []
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.02), ncol=3, fontsize=7.5, frameon=False)
    fig.suptitle("Run time against pressure error, hard spheres, one thread (stepper: accuracy.json; "
                 "peers: cross_validation.json, a later run and build)", fontsize=10)
    fig.text(0.01, 0.005, MACHINE, fontsize=6.5, color="0.3")
    fig.tight_layout(rect=(0, 0.16, 1, 0.96))
    fig.savefig(out / "pareto_time_error.png", dpi=130)
    plt.close(fig)
    return summary, fronts


def eos_series():
    """(label, marker, colour, hollow, [(phi, z, z_err)]) of every hard-sphere Z at a monodisperse state."""
    eos = load(EOS)
    series = [("event engine, N = 4000 (eos.json)", "o", "C0", False, [(d["phi"], d["z"], d["z_err"]) for d in eos])]
    picks = [("event engine reference run", "s", "C3", dict(engine="event", reference=True)),
             ("stepper double dt = 0.01", "^", "C2", dict(engine="stepper", default=True, precision="double")),
             ("stepper float dt = 0.01", "v", "C1", dict(engine="stepper", default=True, precision="float")),
             ("lmp_hs (fix hardsphere) dt = 0.01", "D", "C4", dict(engine="lmp_hs", ranks=1))]
    for n in (8000, 64000):
        for label, marker, colour, match in picks:
            rows = xv_rows(n=n, composition="mono", **match)
            series.append((f"{label}, N = {n} (xv)", marker, colour, n != 8000,
                           [(r["phi"], r["Z"], r["Z_err"]) for r in rows]))
    return series


def fig_eos(out):
    series = eos_series()
    fig, ax = plt.subplots(figsize=(7.5, 6.2))
    phi = np.linspace(0.05, 0.5, 100)
    ax.plot(phi, 100 * (z_cs(phi) / z_kolafa(phi) - 1), "k--", lw=1, label="Carnahan-Starling")
    ax.axhline(0, color="k", lw=0.8)
    worst = {}
    for i, (label, marker, colour, hollow, pts) in enumerate(series):
        half = (len(series) - 1) // 2  # eos.json (i = 0) at its phi; N = 8000 to the left, 64000 to the right
        dx = 0.0036 * (0 if i == 0 else i - half - 1 if i <= half else i - half)
        x = np.array([p[0] for p in pts]) + dx
        res = [100 * (z / z_kolafa(p) - 1) for p, z, _ in pts]
        err = [100 * e / z_kolafa(p) for p, _, e in pts]
        ax.errorbar(x, res, err, fmt=marker, ms=5, capsize=2, lw=0.8, color=colour, label=label,
                    mfc="white" if hollow else colour, zorder=3 if i else 4)
        worst[label] = max(((abs(r), r / e if e else 0, p[0]) for r, e, p in zip(res, err, pts)), default=None)
    ax.set_xlabel("packing fraction φ (points offset sideways for legibility)")
    ax.set_ylabel("(Z − Z_Kolafa) / Z_Kolafa  [%]")
    ax.set_title("Equation of state against Kolafa: monodisperse hard spheres, N = 4000 (eos.json),\n"
                 "N = 8000 and 64000 (cross_validation.json, 'xv'), 1σ error bars", fontsize=10)
    ax.legend(fontsize=7, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.13), frameon=False)
    fig.tight_layout()
    fig.savefig(out / "eos_kolafa.png", dpi=130)
    plt.close(fig)
    parts = [f"{lab.rsplit(' (', 1)[0]}: {w[0]:.3f}% ({w[1]:+.1f} sigma, phi {w[2]:g})"
             for lab, w in worst.items() if w]
    return ["eos: largest |Z/Z_Kolafa - 1| per series: " + "; ".join(parts),
            f"eos: Carnahan-Starling against Kolafa at phi 0.45: {100 * (z_cs(0.45) / z_kolafa(0.45) - 1):+.3f}%"]


def collisions_per_cpu(rate, n, cpu_per_time):
    """Collisions per CPU second; rate counts each collision for both spheres (collisions/time = rate N / 2)."""
    return rate * n / 2 / cpu_per_time


def fig_collisions(out):
    acc, eos, speed = load(ACCURACY), load(EOS), load(SPEED)
    fig, (ae, ast) = plt.subplots(1, 2, figsize=(11, 5.6), sharex=True, sharey=True)
    sp = sorted(speed, key=lambda d: d["n"])
    ae.plot([d["n"] for d in sp], [d["collisions_per_second"] for d in sp], "o-", color=PHI_COLOUR[0.45])
    for d in eos:
        ae.plot(d["n"], d["collisions_per_second"], "P", color=PHI_COLOUR[d["phi"]], mfc="none", ms=8)
    summary = ["collisions/s: event engine phi 0.45 (speed.json): " +
               ", ".join(f"N {d['n']}: {d['collisions_per_second']:.3g}" for d in sp),
               "collisions/s: event engine N 4000 (eos.json, first build): " +
               ", ".join(f"phi {d['phi']:g}: {d['collisions_per_second']:.3g}" for d in eos)]
    for ax, engine, match in ((ae, "event", dict(engine="event", reference=True)),
                              (ast, "stepper", dict(engine="stepper", default=True, precision="float"))):
        for phi in (0.1, 0.3, 0.45):
            rows = sorted(xv_rows(composition="mono", phi=phi, **match), key=lambda r: r["n"])
            y = [collisions_per_cpu(r["collision_rate"], r["n"], r["cpu_seconds_per_tau"]) for r in rows]
            ax.plot([r["n"] for r in rows], y, "s--", color=PHI_COLOUR[phi], lw=1)
            summary.append(f"collisions/s: {engine} phi {phi:g} (xv): " +
                           ", ".join(f"N {r['n']}: {v:.3g}" for r, v in zip(rows, y)))
        pick = [r for r in acc if r["engine"] == engine
                and (engine == "event" or (r["precision"], r["detect"], r["dt"]) == ("float", "overlap", 0.01))]
        for r in sorted(pick, key=lambda r: (r["phi"], r["n"])):
            v = collisions_per_cpu(r["rate"], r["n"], r["cpu_per_time"])
            ax.plot(r["n"], v, "o", color=PHI_COLOUR[r["phi"]], mfc="none", ms=9, mew=1.5)
            summary.append(f"collisions/s: {engine} phi {r['phi']:g} N {r['n']} (accuracy.json): {v:.3g}")
    for ax, title in ((ae, "Event engine (exact)"), (ast, "Stepper, float, dt = 0.01, overlap detection")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("number of spheres N")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="both", lw=0.3, color="0.85")
    ae.set_ylabel("collisions per CPU second")
    ticks = [2e5, 3e5, 5e5, 1e6, 2e6, 3e6]
    ae.set_yticks(ticks, [f"{t:.0e}".replace("e+0", "e") for t in ticks])
    ae.minorticks_off()
    line = matplotlib.lines.Line2D
    phis = [line([], [], color=c, lw=6) for c in PHI_COLOUR.values()]
    fig.legend(phis, [f"φ = {p:g}" for p in PHI_COLOUR], loc="lower center", bbox_to_anchor=(0.5, 0.13), ncol=6,
               fontsize=8, frameon=False)
    src = [(line([], [], color="k", marker="o"), "speed.json: event engine, φ = 0.45 (commit d2f50e2)"),
           (line([], [], color="k", marker="P", mfc="none", ls=""),
            "eos.json: event engine, N = 4000 (first build, f4f23bb)"),
           (line([], [], color="k", marker="s", ls="--", lw=1),
            "cross_validation.json (build 367c32e; event: reference runs)"),
           (line([], [], color="k", marker="o", mfc="none", ls="", ms=9), "accuracy.json (commit e69c738)")]
    fig.legend(*zip(*src), loc="lower center", bbox_to_anchor=(0.5, 0.03), ncol=2, fontsize=8, frameon=False)
    fig.suptitle("Collisions per CPU second against N, monodisperse hard spheres, one thread "
                 "(collisions per unit time = rate N / 2)", fontsize=10)
    fig.text(0.01, 0.005, MACHINE + " The sources were measured with different builds.", fontsize=6.5, color="0.3")
    fig.tight_layout(rect=(0, 0.2, 1, 1))
    fig.savefig(out / "collisions_per_second.png", dpi=130)
    plt.close(fig)
    return summary


def main(argv=None):
    p = harness.parser(__doc__, out_default=str(ROOT / "docs" / "reports" / "figures"))
    a = p.parse_args(argv)
    session = harness.Session("compare.docs_figures", a, argv)
    out = session.out()
    lines, _ = fig_pareto(out)
    for line in lines + fig_eos(out) + fig_collisions(out):
        session.log(line)
    return session.finish([])


if __name__ == "__main__":
    harness.main(main)
