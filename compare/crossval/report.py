"""cross_validation.md and its figures for the cross-validation (python3 -m compare.cross_validate)."""
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

from compare.crossval import analysis as xv_analysis  # noqa: E402
from compare.machine_info import versions  # noqa: E402



def save_panel(fig, ax, out, name, xlabel, ylabel, title):
    """Labels one panel, writes the figure to out/name and closes it; returns name."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=5)
    fig.tight_layout()
    fig.savefig(out / name, dpi=130)
    plt.close(fig)
    return name

def fmt(x, digits=4):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:.{digits}g}"


def pm(v, e, digits=4):
    return f"{fmt(v, digits)} ± {fmt(e, 2)}" if e is not None and not math.isnan(e) else fmt(v, digits)


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    return "\n".join(lines + ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]) + "\n"


def cheapest(rows, key="within_1pct"):
    ok = [r for r in rows if r[key]]
    return min(ok, key=lambda r: r["cpu_seconds_per_tau"]) if ok else None


ENGINE_NAMES = {"event": "event engine", "stepper": "stepper", "lmp_hs": "lmp_hs (fix hardsphere)",
                "lammps hooke": "LAMMPS gran/hooke", "lammps hertz": "LAMMPS gran/hertz/history",
                "liggghts hertz": "LIGGGHTS hertz"}


def timing_rows(rows, state):
    """Per engine (and precision, ranks): its cheapest setting within 1% of the precise Z."""
    rs = [r for r in rows if r["state"] == state and not r["reference"]]
    groups = {}
    for r in rs:
        name = ENGINE_NAMES[r["engine"]] + (f" {r['precision']}" if r["engine"] == "stepper" else "") + \
            (f", {r['ranks']} ranks" if r["ranks"] > 1 else "")
        groups.setdefault(name, []).append(r)
    ev = next((r for r in rows if r["state"] == state and r["reference"]), None)
    base = cheapest(groups.get("stepper double", []))
    out = []
    for name, g in groups.items():
        g = [r for r in g if r]
        c = cheapest(g) if name != "event engine" else ev  # exact: its long run is the reference
        cm = cheapest(g, "within_1pct_mapped") if g[0]["kind"] == "soft" else None
        def ratio(r):
            return fmt(r["cpu_seconds_per_tau"] / base["cpu_seconds_per_tau"], 3) if r and base else "-"

        out.append([name, c["setting"] if c else "none in the sweep", fmt(c and c["cpu_seconds_per_tau"], 3),
                    cm["setting"] if cm else ("-" if g[0]["kind"] == "hard" else "none in the sweep"),
                    fmt(cm and cm["cpu_seconds_per_tau"], 3), ratio(c), ratio(cm)])
    return out


def ratio_table(rows, states):
    """Engines x states: CPU time per tau at matched accuracy over the stepper's (double)."""
    table_rows, names = {}, []
    for state in states:
        for name, _, _, _, _, ratio_raw, ratio_mapped in timing_rows(rows, state):
            if name not in table_rows:
                table_rows[name], _ = {}, names.append(name)
            table_rows[name][state] = ratio_raw + ("" if ratio_mapped == "-" else f" / {ratio_mapped}")
    return table(["engine"] + states, [[n] + [table_rows[n].get(s, "-") for s in states] for n in names])


def convergence_order(rows, key):
    """Exponent a of |Z - Z_ref| ~ shift^a over a sweep (None when fewer than 3 points above noise)."""
    pts = [(r["bh_shift"], abs(r[key] - r["Z_ref"])) for r in rows
           if r[key] is not None and abs(r[key] - r["Z_ref"]) > 2 * r["Z_err"]]
    if len(pts) < 3:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def fig_speeds(out, rows, curves, state):
    fig, ax = plt.subplots(figsize=(6, 4))
    u = np.linspace(0, 4.5, 200)
    ax.plot(u, stats.maxwell.pdf(u), "k-", lw=2, label="Maxwell-Boltzmann")
    rs = [r for r in rows if r["state"] == state]
    stiffest = {}  # legend: every hard run, and each soft engine at its stiffest setting
    for r in rs:
        if r["kind"] == "soft":
            stiffest[r["engine"]] = min(stiffest.get(r["engine"], r["bh_shift"]), r["bh_shift"])
    for r in rs:
        bins, h = curves[(state, r["setting"])]["speeds"]
        labelled = r["kind"] == "hard" or r["bh_shift"] == stiffest[r["engine"]]
        ax.step(0.5 * (bins[1:] + bins[:-1]), h, where="mid", lw=0.8, alpha=0.7,
                label=f"{r['setting']} (p={r['ks_p']:.2f})" if labelled else None)
    return save_panel(fig, ax, out, f"speeds_{state}.png", "speed v sqrt(m/kT)", "probability density",
                      f"Speeds, {state}")


def fig_rdf(out, rows, curves, state):
    keys = sorted(k for k in curves[(state, rows[0]["setting"])]["rdf"] if k != "all") if rows else []
    fig, axes = plt.subplots(1, len(keys), figsize=(5 * len(keys), 3.8), squeeze=False)
    for ax, key in zip(axes[0], keys):
        for r in rows:
            if r["state"] != state or (r["kind"] == "soft" and r["steps_per_contact"] != 20):
                continue
            if r["engine"] == "stepper" and not r["default"]:
                continue
            rr, g = curves[(state, r["setting"])]["rdf"][key]
            ax.plot(rr, g, lw=0.8, label=r["setting"])
        ax.set_xlim(0.8, 3)
        ax.set_xlabel("r / sigma")
        ax.set_ylabel("g(r)" + (f" types {key}" if len(keys) > 1 else ""))
    axes[0][0].set_title(f"g(r), {state}")
    axes[0][0].legend(fontsize=5)
    fig.tight_layout()
    fig.savefig(out / f"rdf_{state}.png", dpi=130)
    plt.close(fig)
    return f"rdf_{state}.png"


def fig_z_stiffness(out, rows, states):
    fig, axes = plt.subplots(1, len(states), figsize=(4.5 * len(states), 3.8), squeeze=False)
    for ax, state in zip(axes[0], states):
        rs = [r for r in rows if r["state"] == state]
        ref = next(r for r in rs if r["reference"])
        ax.axhspan(ref["Z"] * 0.99, ref["Z"] * 1.01, color="0.85", label="hard spheres ±1%")
        ax.axhline(ref["Z"], color="k", lw=1)
        shifts = set()
        # LIGGGHTS hertz and LAMMPS hertz follow the same force law: hollow markers keep both visible
        for engine, colour, marker, size in zip(xv_analysis.SOFT_MODEL, ("C0", "C1", "C2"), "osD", (4, 4, 8)):
            s = sorted((r for r in rs if r["engine"] == engine and r["ranks"] == 1 and r["steps_per_contact"] == 20),
                       key=lambda r: r["bh_shift"])
            if not s:
                continue
            x = [r["bh_shift"] for r in s]
            shifts.update(x)
            style = dict(color=colour, marker=marker, ms=size, mfc="none" if size > 4 else colour, capsize=2)
            ax.errorbar(x, [r["Z"] for r in s], [r["Z_err"] for r in s], ls="--",
                        label=f"{ENGINE_NAMES[engine]} raw", **style)
            ax.errorbar(x, [r["Z_mapped"] for r in s], [r["Z_err"] for r in s], ls="-",
                        label=f"{ENGINE_NAMES[engine]} mapped", **style)
        ax.set_xscale("log")
        ax.set_xticks(sorted(shifts))
        ax.set_xticklabels([f"{v:g}" for v in sorted(shifts)], rotation=45, fontsize=7)
        ax.minorticks_off()
        ax.set_xlabel("Barker-Henderson shift (sigma - d) of a unit pair")
        ax.set_ylabel("Z")
        ax.set_title(state, fontsize=9)
    axes[0][0].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(out / "z_stiffness.png", dpi=130)
    plt.close(fig)
    return "z_stiffness.png"


def fig_msd(out, rows, curves, state):
    fig, ax = plt.subplots(figsize=(6, 4))
    for r in rows:
        if r["state"] != state or (r["engine"] == "stepper" and not r["default"]):
            continue
        if r["kind"] == "soft" and r["steps_per_contact"] != 20:
            continue
        tau, msd = curves[(state, r["setting"])]["msd"]
        ax.plot(tau, msd, lw=0.8, label=f"{r['setting']} D={fmt(r['D'])}")
    return save_panel(fig, ax, out, f"msd_{state}.png", "t / tau", "MSD / sigma^2",
                      f"Mean-squared displacement, {state}")


def state_table(rows, state):
    header = ["engine, setting", "Z", "Z mapped", "KS p", "D", "collisions / sphere / tau", "g(contact)",
              "energy drift", "CPU s / tau", "CPU µs / particle-step"]
    out = []
    for r in rows:
        if r["state"] != state:
            continue
        g = ", ".join(f"{k}: {pm(v['g'], v['err'], 3)}" for k, v in r["g_contact"].items())
        out.append([r["setting"], pm(r["Z"], r["Z_err"]), fmt(r["Z_mapped"]), fmt(r["ks_p"], 2),
                    pm(r["D"], r["D_err"], 3), pm(r["collision_rate"], r["collision_rate_err"]), g,
                    fmt(r["energy_drift"], 2), fmt(r["cpu_seconds_per_tau"], 3),
                    fmt(r["cpu_seconds_per_particle_step"] and 1e6 * r["cpu_seconds_per_particle_step"], 3)])
    return table(header, out)


def write_report(out, plan, rows, curves, failures, tools, seed):
    out = Path(out)
    v = versions(tools)
    states = [s.label for s in plan.states]
    first = states[0] if plan.mode == "quick" else next(s for s in states if "mono_n8000_phi0.3" in s)
    lines = ["# Cross-validation: hard-sphere engines against LAMMPS granular and LIGGGHTS", ""]
    verdict = "all engines agree within the tolerances" if not failures else f"{len(failures)} disagreements"
    lines += [f"**{verdict}** ({plan.mode} run: {len(rows)} runs over {len(states)} states).", ""]
    lines += [f"Machine: {v['machine']}. hardsphere {v['hardsphere']} built with {v['compiler']}; LAMMPS "
              f"{v['lammps']}; {v['liggghts']}; {v['mpi']}.", ""]
    lines += ["Reproduce: `/usr/bin/python3 -m compare.cross_validate " + ("--quick " if plan.mode == "quick" else "")
              + "--out DIR`. Units sigma = m = kT = 1, tau = sigma sqrt(m/kT).", ""]
    if failures:
        lines += ["## Disagreements", ""] + [f"- {f}" for f in failures] + [""]
    lines += ["## Tolerances", "",
              f"- Hard engines' Z agree within {plan.tolerances['hard_z_sigmas']:g} combined standard errors: the "
              "stepper's finest dt (double and float) against the event engine, lmp_hs against the standalone "
              "stepper at the same dt, lmp_hs serial against 2 ranks.",
              f"- Soft engines' mapped Z within {100 * plan.tolerances['soft_mapped_z']:g}% of the event engine's Z "
              "at the stiffest setting of each sweep (or within 3 combined standard errors where those are larger, "
              "as for the quick mode's 1000 spheres).",
              f"- Speeds: KS p-value of one frame's N speeds against Maxwell-Boltzmann at least {plan.tolerances['ks_p']:g}.",
              f"- 'within 1%': |Z / Z_event - 1| <= {100 * plan.tolerances['within']:g}% (the event engine's long "
              "run is the precise hard-sphere value); errors are standard errors of block averages (event engine, "
              "stepper: 8 chained runs, LAMMPS-family: 8 blocks of compute pressure) or of 8 groups of spheres (D).",
              ""]
    lines += ["## Timings at matched accuracy", "",
              "Per engine its cheapest setting whose Z is within 1% of the precise hard-sphere value (soft engines: "
              "raw and Barker-Henderson mapped); CPU seconds per tau of simulated time, all ranks counted; ratio to "
              "the standalone stepper (double) at its cheapest such setting.", ""]
    for n in sorted({int(st.split("_n")[1].split("_")[0]) for st in states}):
        lines += [f"N = {n}:", "", ratio_table(rows, [st for st in states if f"_n{n}_" in st]), ""]
    lines += [
              "Soft engines: raw / Barker-Henderson mapped ('-': no setting of the sweep was within 1%).",
              ""]
    for state in states:
        if not any(r["kind"] == "soft" for r in rows if r["state"] == state):
            continue
        lines += [f"### {state}", "", table(["engine", "cheapest within 1% (raw)", "CPU s / tau",
                                             "cheapest within 1% (mapped)", "CPU s / tau", "ratio (raw)",
                                             "ratio (mapped)"],
                                            timing_rows(rows, state)), ""]
    soft_states = [s for s in states if any(r["state"] == s and r["kind"] == "soft" and r["ranks"] == 1 for r in rows)
                   and len({r["bh_shift"] for r in rows if r["state"] == s and r["kind"] == "soft"}) > 1]
    if soft_states:
        lines += ["## Pressure against stiffness", "", f"![Z against stiffness]({fig_z_stiffness(out, rows, soft_states)})",
                  "", "Measured order of convergence, |Z - Z_hard| ~ shift^a (points more than 2 standard errors "
                  "from the hard value; Hooke's shift ~ kn^-1/2, Hertz's ~ kn^-2/5):", ""]
        conv = []
        for s in soft_states:
            for engine in xv_analysis.SOFT_MODEL:
                sweep = [r for r in rows if r["state"] == s and r["engine"] == engine and r["ranks"] == 1
                         and r["steps_per_contact"] == 20]
                if sweep:
                    conv.append([s, ENGINE_NAMES[engine], fmt(convergence_order(sweep, "Z"), 3),
                                 fmt(convergence_order(sweep, "Z_mapped"), 3)])
        lines += [table(["state", "engine", "a (raw)", "a (mapped)"], conv), ""]
    lines += ["## Distributions", "", f"![speeds]({fig_speeds(out, rows, curves, first)})",
              f"![g(r)]({fig_rdf(out, rows, curves, first)})", f"![MSD]({fig_msd(out, rows, curves, first)})", ""]
    for s in states:
        if "binary" in s and "n8000_phi0.45" in s:
            lines += [f"![g(r) binary]({fig_rdf(out, rows, curves, s)})", ""]
    lines += ["## Every run", "",
              "Z: compressibility factor; Z mapped: soft engines at the Barker-Henderson packing fraction, "
              "carried to the nominal one by BMCSL; D: self-diffusion from the MSD slope; collisions (soft: "
              "contacts started); g(contact) per pair of types, extrapolated from outside; energy drift: "
              "kinetic (+ elastic overlap energy for soft engines) over the frames. References per state: BMCSL "
              "(Carnahan-Starling) Z and contact values, Enskog collision rate and D.", ""]
    for state in states:
        rs = [r for r in rows if r["state"] == state]
        r0 = rs[0]
        ref = f"BMCSL Z {r0['Z_bmcsl']:.4f}, Enskog collision rate {r0['collision_rate_enskog']:.4f}" + (
            f", Enskog D {r0['D_enskog']:.4f}" if r0["D_enskog"] else "") + ", BMCSL g(contact) " + ", ".join(
            f"{k}: {v['bmcsl']:.3f}" for k, v in r0["g_contact"].items())
        lines += [f"### {state}", "", ref, "", state_table(rows, state), ""]
    if seed:
        frag = Path(out) / "seed_figures.md"
        lines += ["## The seed paper's figures 1-3", "", frag.read_text() if frag.exists() else "", ""]
    (out / "cross_validation.md").write_text("\n".join(lines) + "\n")
    return out / "cross_validation.md"
