"""The report of compare.cooling: cooling.md's text and tables, its figures and the plain
statements about the measured differences (computed from the numbers)."""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from compare import hard_sphere_theory as hs_theory  # noqa: E402
from compare.cooling_runs import (ENGINES, EQUILIBRATE, FRAMES, NAMES, PAIR_PHASES, PAIR_SPEEDS, PHI,  # noqa: E402
                                  SOFT_ENGINES, STEPPER_DT, STEPS_PER_CONTACT, engine_tolerance, frame_dt,
                                  pair_summary)
from compare.crossval import plan as xv_plan  # noqa: E402
from compare.crossval.report import fmt, table  # noqa: E402


STYLE = {"stepper": ("C0", "o"), "event": ("C1", "s"), "lammps hooke": ("C2", "^"), "liggghts hertz": ("C3", "v")}


def fig_temperature(out, results, ensembles, t0, gamma0):
    es = list(results)
    fig, axes = plt.subplots(2, len(es), figsize=(5.2 * len(es), 6.4), squeeze=False,
                             gridspec_kw=dict(height_ratios=(2.2, 1.2)), sharex="col")
    for col, e in enumerate(es):
        top, bottom = axes[0, col], axes[1, col]
        t_end = max(max(r["times"]) for r in results[e].values())
        t = np.linspace(0, t_end, 200)
        top.plot(t, hs_theory.haff_temperature(t, t0, float(e), gamma0) / t0, "k-", lw=1.5, label="Haff (Enskog rate)")
        bottom.axhline(0, color="k", lw=1)
        ens = ensembles[e]
        mean, std = 100 * np.array(ens["mean"]), 100 * np.array(ens["std"])
        bottom.fill_between(ens["times"], mean - std, mean + std, color="0.85",
                            label=f"event engine, {len(ens['seeds'])} other states: mean +- s.d.")
        for engine, r in results[e].items():
            c, m = STYLE[engine]
            top.plot(r["times"], np.array(r["T"]) / t0, m, color=c, ms=4, mfc="none", label=NAMES[engine])
            bottom.plot(r["times"], 100 * np.array(r["rel_deviation"]), m + "-", color=c, ms=3, lw=0.8, mfc="none")
        top.set_yscale("log")
        top.set_ylabel("T / T0")
        top.set_title(f"e = {e}")
        top.legend(fontsize=7)
        bottom.legend(fontsize=7, loc="upper left")
        bottom.set_xlabel("t (sigma sqrt(m / T0))")
        bottom.set_ylabel("T / T_Haff - 1 (%)")
    fig.tight_layout()
    fig.savefig(out / "cooling_T.png", dpi=130)
    plt.close(fig)
    return "cooling_T.png"


def fig_speed(out, results, settings):
    es = list(results)
    engines = [g for g in ENGINES if any(g in results[e] for e in es)]
    fig, ax = plt.subplots(figsize=(6, 3.8))
    width = 0.8 / len(es)
    for k, e in enumerate(es):
        x = np.arange(len(engines)) + (k - (len(es) - 1) / 2) * width
        y = [results[e][g]["cpu_seconds_per_unit_time"] if g in results[e] else np.nan for g in engines]
        ax.bar(x, y, width, label=f"e = {e}", color=f"C{k}", alpha=0.8)
    ax.set_xticks(np.arange(len(engines)))
    ax.set_xticklabels([NAMES[g] for g in engines], fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("CPU seconds per unit simulated time")
    ax.set_title(f"N = {settings['n']}, phi = {PHI}; soft: BH shift {settings['soft_shift']}, "
                 f"dt = t_c / {settings['steps_per_contact']}", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "cooling_speed.png", dpi=130)
    plt.close(fig)
    return "cooling_speed.png"


def result_rows(per_engine, ens, tolerances):
    base = per_engine.get("stepper")
    rows = []
    for engine, r in per_engine.items():
        tol = engine_tolerance(ens, engine, tolerances)
        ratio = r["cpu_seconds_per_unit_time"] / base["cpu_seconds_per_unit_time"] if base else None
        diff = r["rel_deviation"][-1] - ens["mean"][-1]
        rows.append([NAMES[engine], f"{100 * r['max_abs_deviation']:.2f}% (t = {r['max_at_time']:.3g})",
                     f"{100 * tol:.2f}%", f"{100 * r['rel_deviation'][-1]:+.2f}%",
                     f"{100 * diff:+.2f}% ({diff / ens['std'][-1]:+.1f} s.d.)",
                     fmt(r["cpu_seconds_per_unit_time"], 3), fmt(ratio, 3)])
    return rows


def settings_rows(soft_by_e, t_end, gamma0):
    dts = ", ".join(f"{frame_dt(t, STEPPER_DT):.5g} for e = {e}" for e, t in t_end.items())
    rows = [["stepper", f"dt = {dts} (the largest <= {STEPPER_DT} that meets the measuring times); TC model "
             "contact time 1e-4 (the default)", "-", "-"],
            ["event engine", "exact; TC model contact time 1e-4 (the default)", "-", "-"]]
    for e, per_engine in soft_by_e.items():
        for engine, s in per_engine.items():
            if engine == "lammps hooke":
                what = f"kn = {s['stiffness']:.4g}, gamman = {s['gamman']:.5g}, dt = {s['dt']:.3g}"
            else:
                what = f"Y = {s['stiffness']:.4g} (nu = 0.3), coefficientRestitution {e}, dt = {s['dt']:.3g}"
            rows.append([f"{NAMES[engine]}, e = {e}", what, fmt(s["contact_time"], 3),
                         fmt(s["contact_time"] * gamma0, 2)])
    return rows


def pair_rows(pair_checks):
    rows = []
    for e, per_engine in pair_checks.items():
        for engine, pairs in per_engine.items():
            rows.append([NAMES[engine], e] + [f"{100 * x['mean_rel_error']:+.3f}% / {100 * x['max_abs_rel_error']:.3f}%"
                                              for x in pair_summary(pairs)])
    return rows


def markdown(data, figs, generated):
    s = data["settings"]
    lines = [
        "# Cooling of a dilute granular gas: Haff's law in every engine", "",
        generated, "",
        "## Set-up", "",
        f"{s['n']} unit spheres (diameter 1, mass 1) at packing fraction {s['phi']:.4g} in a periodic cube, "
        f"from `hardsphere run --phi {PHI} --write-data` (Maxwell-Boltzmann velocities, zero momentum) after an "
        f"elastic event-engine run of {EQUILIBRATE} time units; every engine reads this data file. "
        f"T0 = {s['T0']:.6f} (T = sum m v^2 / 3N). Normal restitution e, no friction (no spin), no gravity.", "",
        "Haff's law T(t) = T0 / (1 + (1 - e^2) Gamma0 t / 6)^2 with the Enskog collision rate at T0, "
        f"Gamma0 = 4 n sigma^2 g(sigma) sqrt(pi T0 / m) = {s['gamma0']:.5f} (Carnahan-Starling g = "
        f"{s['g_contact']:.5f}). T is measured at {FRAMES} equal intervals up to the time where Haff's law "
        "gives T0/3: " + ", ".join(f"t = {t:.4g} for e = {e}" for e, t in s["t_end"].items()) + ".", "",
        "| engine | model and settings | contact time t_c | t_c Gamma0 |", "|---|---|---|---|",
    ]
    lines += ["| " + " | ".join(r) + " |" for r in settings_rows(data["soft_settings"], s["t_end"], s["gamma0"])]
    lines += [
        "",
        f"The soft stiffnesses give a Barker-Henderson shift of {s['soft_shift']} diameters for a unit pair at T = 1 "
        f"(as in the cross-validation); dt = contact time / {STEPS_PER_CONTACT} (Hertz: at relative speed "
        f"{xv_plan.FAST_PAIR_SPEED}), made a little smaller so that every engine measures at the same times. "
        "The table's t_c is the damped Hookean contact time, and for Hertz the elastic one at the mean "
        "relative speed sqrt(8 T0 / (pi meff)) (it grows as v^(-1/5) as the gas cools). "
        "LAMMPS's gran/hooke normal force is kn delta - meff gamman v_n, a damped oscillator "
        "delta'' + gamman delta' + (kn/meff) delta = 0 whose restitution is e = exp(-gamman t_c / 2) with "
        "t_c = pi / sqrt(kn/meff - gamman^2/4); so gamman = 2 |ln e| sqrt(kn/meff) / sqrt(pi^2 + ln^2 e). "
        "LIGGGHTS's hertz damping -2 sqrt(5/6) beta sqrt(Sn meff) v_n, beta = ln e / sqrt(ln^2 e + pi^2), "
        "gives e exactly in continuous time.", "",
        "### Two-sphere check of the soft restitution", "",
        "Head-on pairs of unit spheres through each soft input at the cooling run's stiffness and time step, "
        f"at relative normal speeds v and {len(PAIR_PHASES)} phases of the contact's start within a time step; "
        "exit over entry normal speed against e: mean relative error over the phases / largest absolute one. "
        "The damping force does not vanish at zero overlap, so it switches on and off within a step and the "
        f"integrator's error is first order in dt (hence {STEPS_PER_CONTACT} steps per contact). A relative error "
        "x in e changes the cooling rate (1 - e^2) by -2 e^2 x / (1 - e^2): -8.5 x at e = 0.9, -1.9 x at e = 0.7.",
        "",
        table(["engine", "e"] + [f"v = {v}" for v in PAIR_SPEEDS], pair_rows(data["pair_checks"])),
        "## Results", "",
        f"Tolerances on max |T/T_Haff - 1| over the measured times (t <= the T0/3 time): for hard-sphere engines "
        f"the ensemble's largest |mean| + {s['tolerances']['sigmas']:g} s.d. over those times, for soft engines "
        f"{100 * s['tolerances']['soft_model']:g}% more; the two-sphere restitution "
        f"within {100 * s['tolerances']['pair_restitution']:g}% of e. The ensemble: the event engine from "
        f"{s['ensemble_states']} further states made like the first (seeds 2, 3, ...), whose mean of T/T_Haff - 1 is "
        "the hard-sphere curve without one state's fluctuations and whose standard deviation (s.d.) is the "
        "scatter of a single run. CPU time: the engines' loop time (output excluded) per unit of simulated "
        "time, one core each, single runs on a 2-core machine shared with other work, so contention can "
        "inflate a figure.", "",
    ]
    for e, per_engine in data["results"].items():
        lines += [f"### e = {e}", "",
                  table(["engine", "max abs(T/T_Haff - 1)", "tolerance", "T/T_Haff - 1 at T0/3",
                         "minus the ensemble mean", "CPU s per unit time", "ratio to the stepper"],
                        result_rows(per_engine, data["ensemble"][e], s["tolerances"]))]
    lines += [f"![T(t) against Haff's law]({figs[0]})", "", f"![CPU time per unit simulated time]({figs[1]})", "",
              "## Verdict", ""]
    if data["failures"]:
        lines += ["Disagreements (exit status 1):", ""] + [f"* {f}" for f in data["failures"]]
    else:
        lines += ["Every engine is within its tolerance (exit status 0)."]
    lines += ["", "## Differences", ""] + [f"* {n}" for n in data["notes"]] + [""]
    return "\n".join(lines)


def notes(data):
    """Plain statements about the measured differences, from the numbers."""
    out = []
    gamma0 = data["settings"]["gamma0"]
    for e, per in data["results"].items():
        ens = data["ensemble"][e]
        mean, sd = ens["mean"][-1], ens["std"][-1]
        se = sd / math.sqrt(len(ens["seeds"]))
        text = (f"e = {e}, hard spheres against Haff's law: at T0/3 the ensemble has T/T_Haff - 1 = "
                f"{100 * mean:+.2f}% (standard error {100 * se:.2f}%, single-run s.d. {100 * sd:.2f}%)")
        spread = max(abs(r["rel_deviation"][-1] - mean) for r in per.values()) / sd
        if abs(mean) > 3 * se:
            text += (f"; the hard-sphere gas cools {'more slowly' if mean > 0 else 'faster'} than Haff's law with the "
                     f"Enskog rate predicts, and every engine's run lies within {spread:.1f} s.d. of that mean, so "
                     "this is the law's approximation (molecular chaos and a Maxwellian velocity distribution "
                     "throughout the cooling), not an engine's error.")
        else:
            text += "; no deviation beyond the scatter."
        out.append(text)
        diffs = []
        for g in SOFT_ENGINES:
            if g in per:
                d = per[g]["rel_deviation"][-1] - mean
                tcg = data["soft_settings"][e][g]["contact_time"] * gamma0
                diffs.append(f"{NAMES[g]} {100 * d:+.2f}% ({d / sd:+.1f} s.d.; t_c Gamma0 = {tcg:.4f})")
        if diffs:
            out.append(f"e = {e}, soft against hard spheres at T0/3 (minus the ensemble mean): " + ", ".join(diffs)
                       + ". A soft contact takes t_c, so the soft gas is expected to differ by O(t_c Gamma0) "
                       "plus the restitution error of the two-sphere check times its amplification "
                       "2 e^2 / (1 - e^2) in the cooling rate; a difference within ~2 s.d. is the scatter of one run.")
    for e, per in data["results"].items():
        same = {g: shared_until(per["event"], r) for g, r in per.items() if g != "event"}
        out.append(f"e = {e}: from the shared state, T agrees with the event engine's to {100 * SHARED:g}% until t = "
                   + ", ".join(f"{same[g]:.3g} ({NAMES[g]})" for g in same)
                   + f" ({gamma0:.3g} collisions per sphere per unit time at T0). The runs share the state's early "
                   "fluctuations a little longer and then decorrelate, so single runs are compared with the "
                   "ensemble mean and s.d. rather than with each other.")
    s = data["settings"]
    out.append("Cost: the soft engines' CPU time per unit time is proportional to 1/dt = "
               f"{s['steps_per_contact']} / t_c, and t_c to the Barker-Henderson shift ({s['soft_shift']} here): "
               "halving the steps per contact halves it, halving the shift doubles it.")
    return out


SHARED = 5e-4  # relative difference in T below which two runs still follow one trajectory


def shared_until(a, b):
    """The last measured time up to which two runs' temperatures agree to SHARED."""
    ta, tb = np.array(a["T"]), np.array(b["T"])
    apart = np.flatnonzero(np.abs(tb / ta - 1.0) > SHARED)
    k = apart[0] - 1 if len(apart) else len(ta) - 1
    return float(a["times"][k])
