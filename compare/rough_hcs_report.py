"""The report of compare.rough_hcs: rough_hcs.md's text and tables and its two figures."""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from compare import rough_theory as rt  # noqa: E402


def fig_temperatures(out, results):
    cols = min(4, len(results))
    rows = math.ceil(len(results) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.2 * rows), squeeze=False)
    for ax, r in zip(axes.flat, results):
        t = np.array(r["times"])
        for engine, style in (("event", "o"), ("stepper", "s")):
            m = r["engines"].get(engine)
            if not m:
                continue
            c = m["curves"][0]
            ax.plot(t, c["T"], style, color="C0", mfc="none", ms=4, label=f"T_tr {engine}")
            ax.plot(t, c["Trot"], style, color="C3", mfc="none", ms=4, label=f"T_rot {engine}")
        c = r["engines"][next(iter(r["engines"]))]["curves"][0]
        ax.plot(t, c["T_theory"], "-", color="C0", lw=1, label="theory")
        ax.plot(t, c["Trot_theory"], "-", color="C3", lw=1)
        ax.set_yscale("log")
        case = r["case"]
        title = f"e = {case['e']}, beta = {case['beta']}" + ("" if case["mu"] is None else f", mu = {case['mu']}")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("t (d sqrt(m / T0))", fontsize=8)
        ax.set_ylabel("T / T0", fontsize=8)
    axes.flat[0].legend(fontsize=6)
    for ax in list(axes.flat)[len(results):]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(out / "rough_hcs_T.png", dpi=110)
    plt.close(fig)


def fig_ratio(out, results, q):
    walton = [r for r in results if r["case"]["mu"] is not None]
    fig, axes = plt.subplots(1, 2 if walton else 1, figsize=(10 if walton else 5.5, 4), squeeze=False)
    ax = axes[0, 0]
    betas = np.linspace(-0.9, 1.0, 200)
    for e, color in ((0.95, "C2"), (0.9, "C0"), (0.7, "C1")):
        ax.plot(betas, [rt.scaling_ratio(e, b, q) for b in betas], "-", color=color, lw=1, label=f"theory e = {e}")
        for r in results:
            if r["case"]["e"] == e and r["case"]["mu"] is None:
                for engine, mk in (("event", "o"), ("stepper", "s")):
                    if engine in r["engines"]:
                        m = r["engines"][engine]
                        ax.errorbar(r["case"]["beta"], m["R"], yerr=m["R_err"], fmt=mk, color=color, mfc="none",
                                    capsize=2)
    ax.set_xlabel("tangential restitution beta")
    ax.set_ylabel("R = T_rot / T_tr of the scaling state")
    ax.set_ylim(0, 2)
    ax.legend(fontsize=7)
    ax.set_title("constant beta (o event engine, s stepper)", fontsize=9)
    if not walton:
        fig.tight_layout()
        fig.savefig(out / "rough_hcs_R.png", dpi=110)
        plt.close(fig)
        return
    bx = axes[0, 1]
    for r in walton:
        c = r["case"]
        for engine, mk in (("event", "o"), ("stepper", "s")):
            if engine in r["engines"]:
                m = r["engines"][engine]
                bx.errorbar(c["mu"], m["R"], yerr=m["R_err"], fmt=mk, color="k", mfc="none", capsize=2)
        bx.plot(c["mu"], r["theory"]["R"], "x", color="C3", ms=9)
        bx.annotate(f"e = {c['e']}", (c["mu"], r["theory"]["R"]), xytext=(6, 6), textcoords="offset points", fontsize=7)
        for key, color in (("R_sliding", "C2"), ("R_sticking", "C0")):
            if r["theory"].get(key) is not None:
                bx.plot(c["mu"], r["theory"][key], "_", color=color, ms=14, mew=2)
    bx.plot([], [], "x", color="C3", label="Walton, Maxwellian closure (Monte Carlo)")
    bx.plot([], [], "_", color="C2", mew=2, label="all contacts slide")
    bx.plot([], [], "_", color="C0", mew=2, label="all contacts stick (beta0)")
    bx.set_xscale("log")
    bx.set_xlabel("Coulomb friction mu (beta0 = 0.5)")
    bx.set_ylabel("R")
    bx.legend(fontsize=7)
    bx.set_title("Walton friction (e as in the table)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "rough_hcs_R.png", dpi=110)
    plt.close(fig)


def fmt_case(c):
    return f"{c['e']} | {c['beta']} | " + ("-" if c["mu"] is None else f"{c['mu']}")


def markdown(data, generated):
    s = data["settings"]
    PHI, Q, FRAMES, EQUILIBRATE, TOL = s["phi"], s["inertia"], s["frames"], s["equilibrate"], s["tolerance"]
    lines = ["# Homogeneous cooling of rough hard spheres", "",
             generated, "",
             "## Set-up", "",
             f"{s['n']} unit spheres (d = 1, m = 1, I = {Q} m (d/2)^2) at phi {PHI} in a periodic cube, {s['seeds']} "
             f"independent states (seeds 1..{s['seeds']}; each an elastic smooth event-engine run of {EQUILIBRATE} "
             "time units from `hardsphere run --write-data`), angular velocities from Maxwell-Boltzmann at "
             "T_rot0 = R0 T0. Event engine (exact) and stepper (dt <= 0.01). T_tr = sum m |v - v_cm|^2 / 3N, "
             f"T_rot = sum I |w|^2 / 3N from the dumps at {FRAMES} equal intervals up to the theory's T0/3 time.", "",
             "Theory (derivation and Monte Carlo check: `compare/rough_theory.py`, "
             "`tests/compare/test_rough_theory.py`): Huthmann and Zippelius, PRE 56, R6275 (1997); Luding, "
             "Huthmann, McNamara and Zippelius, PRE 58, 3416 (1998). With eta = q (1 + beta) / (2 (1 + q)), "
             "A = (1 - e^2)/4 + eta (1 - eta), B = eta^2 / q, C = (eta / q)(1 - eta / q) and the Enskog frequency "
             "omega = 4 n d^2 chi sqrt(pi T / m) (Carnahan-Starling chi):", "",
             "    dT_tr/dt = -(4/3) omega (A T_tr - B T_rot),   dT_rot/dt = (4/3) omega (B T_tr - C T_rot),", "",
             "and the scaling state's R = T_rot / T_tr is the positive root of B R^2 + (C - A) R - B = 0. "
             "Walton's friction (--friction mu, --tangential-restitution beta0): the same Maxwellian closure "
             "evaluated by a Monte Carlo of the Walton rule (400 000 pairs), with McNamara and Luding's (PRE 58, "
             "2247, 1998) asymptotes: small mu, every contact slides (closed form), large mu, every contact sticks "
             "(constant beta0).", "",
             "Runs: from R0 = 1, T_tr(t) and T_rot(t) against the ODEs from the measured initial temperatures; from "
             "R0 = the theory's R, R measured as the mean of T_rot / T_tr over the second half of the frames. "
             "Sonine level: the comparison is with the Maxwellian (zeroth-order) theory; the column 'Sonine' is the "
             "factor by which the first Sonine correction of Santos, Kremer and dos Santos, Phys. Fluids 23, 030604 "
             "(2011), would change R with the cumulants a20, a02, a11 measured in the scaling runs (the Monte Carlo "
             "weighted by f/f_M, first order in the cumulants).", "",
             f"Pass: R within {100 * TOL:g}% + {s.get('sigmas', 3)} standard errors of the seed mean; T_tr / T_theory - 1 (seed mean) "
             f"within {100 * TOL:g}% + {s.get('sigmas', 3)} standard errors at every measured time.", "",
             "## Scaling ratio R", "",
             "| e | beta (beta0) | mu | engine | R measured | R theory | measured / theory - 1 | Sonine | "
             "a20, a02, a11 | all slide / all stick |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in data["results"]:
        th = r["theory"]
        for engine, m in r["engines"].items():
            dev = "-" if th["R"] is None else f"{100 * (m['R'] / th['R'] - 1):+.2f}% ± {100 * m['R_err'] / th['R']:.2f}%"
            son = "-" if r["sonine_factor"] is None else f"{r['sonine_factor']:.4f}"
            asym = "-" if not r["case"]["mu"] else (
                f"{th['R_sliding']:.4f} / {th['R_sticking']:.4f}" if th.get("R_sliding") else
                f"none / {th['R_sticking']:.4f}")
            lines.append(f"| {fmt_case(r['case'])} | {engine} | {m['R']:.4f} ± {m['R_err']:.4f} | "
                         + ("none" if th["R"] is None else f"{th['R']:.4f}") + f" | {dev} | {son} | "
                         + ", ".join(f"{x:+.3f}" for x in m["cumulants"]) + f" | {asym} |")
    lines += ["", "## Two-temperature cooling from T_rot0 = T_tr0", "",
              "| e | beta (beta0) | mu | engine | T0/3 time | worst T_tr / T_theory - 1 (seed mean ± s.e.) | "
              "max abs(T_rot / T_theory - 1) | CPU s per unit time |", "|---|---|---|---|---|---|---|---|"]
    for r in data["results"]:
        for engine, m in r["engines"].items():
            lines.append(f"| {fmt_case(r['case'])} | {engine} | {r['t_end']:.4g} | {100 * m['T_worst']:+.2f}% ± "
                         f"{100 * m['T_worst_err']:.2f}% (t = {m['T_worst_time']:.3g}) | {100 * m['Trot_max']:.2f}% | "
                         f"{m['cpu_seconds_per_unit_time']:.3g} |")
    lines += ["", "![T_tr and T_rot against time](rough_hcs_T.png)", "", "![R against beta and mu](rough_hcs_R.png)",
              "", "## Verdict", ""]
    if data["failures"]:
        lines += ["Disagreements (exit status 1):", ""] + [f"* {f}" for f in data["failures"]]
    else:
        lines += ["Every case and engine is within its tolerance (exit status 0)."]
    return "\n".join(lines)
