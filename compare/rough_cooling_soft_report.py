"""The report of compare.rough_cooling_soft: rough_cooling_soft.md's text and tables and its figure."""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

SOFT = ("lammps", "liggghts")
NAMES = {"lammps": "LAMMPS granular hooke + linear_history", "liggghts": "LIGGGHTS hertz + tangential history",
         "event": "event engine (Walton)", "stepper": "stepper (Walton)"}


def ratio_at_third(run):
    """R = T_rot / T_tr where the run's T_tr crosses T0/3 (linear in log T between frames), or at
    its end if it stays above (a nearly smooth gas cools more slowly)."""
    t = np.log(np.array(run["T"]) / run["T"][0])
    r = np.array(run["Trot"]) / np.array(run["T"])
    target = math.log(1 / 3)
    below = np.flatnonzero(t <= target)
    if not len(below):
        return float(r[-1])
    k = below[0]
    f = (t[k - 1] - target) / (t[k - 1] - t[k])
    return float(r[k - 1] + f * (r[k] - r[k - 1]))


def figure(out, data):
    E = data["settings"]["e"]
    mus = list(data["results"])
    fig, axes = plt.subplots(1, len(mus), figsize=(5.5 * len(mus), 4.2), squeeze=False)
    style = {"lammps": ("C2", "^"), "liggghts": ("C3", "v"), "event": ("C1", "o"), "stepper": ("C0", "s")}
    for ax, mu in zip(axes[0], mus):
        per = data["results"][mu]
        t = np.array(per["times"])
        for name, r in per.items():
            if name == "times":
                continue
            base = name.split()[0]
            c, m = style[base]
            ls = "-" if base in SOFT or name.endswith("lammps") else "--"
            label = NAMES[base] + ("" if base in SOFT else f", beta0 {r['beta0']:.3f}")
            ax.plot(t, r["T"], m + ls, color=c, ms=4, mfc="none", lw=0.8, label=label)
            ax.plot(t, r["Trot"], m + ls, color=c, ms=4, lw=0.8)
        ax.set_yscale("log")
        ax.set_title(f"e = {E}, mu = {mu}: open T_tr, filled T_rot", fontsize=9)
        ax.set_xlabel("t (d sqrt(m / T0))")
        ax.set_ylabel("T / T0")
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(out / "rough_cooling_soft_T.png", dpi=110)
    plt.close(fig)


def markdown(data, rows, generated):
    s = data["settings"]
    E, STEPS_PER_CONTACT, TOL = s["e"], s["steps_per_contact"], s["tolerance"]
    sl, sg = s["soft"]["lammps"], s["soft"]["liggghts"]
    lines = ["# Cooling of a rough granular gas: hard spheres with Walton's friction against LAMMPS and LIGGGHTS", "",
             generated, "",
             "## Set-up", "",
             f"{s['n']} unit spheres at phi {s['phi']:.4g}, T0 = {s['T0']:.5f}, T_rot0 = T0 (angular velocities from "
             f"Maxwell-Boltzmann, I = 0.4 m r^2), normal restitution e = {E}, Coulomb friction mu = "
             + ", ".join(map(str, s["mus"])) + ". One state read by every engine.", "",
             "| engine | contact model | beta0 | dt |", "|---|---|---|---|",
             f"| LAMMPS 2021 | `pair_style granular`, `hooke {sl['kn']:.5g} {sl['gamman']:.5g} damping mass_velocity "
             f"tangential linear_history {sl['kt']:.5g} 0 mu` (kt = 2/7 kn; no rolling or twisting) | "
             f"{s['beta0']['lammps']:.5f} (rule {s['beta0_rule_lammps']:.5f}) | {sl['dt']:.3g} |",
             f"| LIGGGHTS 3.8 | `gran model hertz tangential history tangential_damping off`, Y = {sg['ymod']:.5g}, "
             f"nu = 0.3, coefficientRestitution {E}, coefficientFriction mu | {s['beta0']['liggghts']:.5f} | "
             f"{sg['dt']:.3g} |",
             "| event engine, stepper | `--restitution 0.9 --tangential-restitution beta0 --friction mu` (Walton), "
             "once with each soft model's beta0 | | exact; dt <= 0.01 |", "",
             f"Soft stiffness: Barker-Henderson shift {s['shift']} of a unit pair at T = 1; dt = contact time / "
             f"{STEPS_PER_CONTACT} (Hertz: at relative speed 6), adjusted so that every engine measures at the same "
             "times. beta0, Walton's sticking limit, from the soft contact's tangential stiffness: a sticking contact's "
             "tangential contact velocity oscillates on the tangential spring with the mass meff q / (1 + q), so "
             "beta0 = -cos(omega_t t_c); linear: omega_t = sqrt(kt (1 + q) / (q meff)), t_c = pi / sqrt(kn/meff - "
             "gamman^2/4). Both soft models' beta0 are measured by a two-sphere oblique contact through their input "
             "with mu = 1e6 (-g_t after / g_t before; the LAMMPS value against the rule in the table).", "",
             "## R = T_rot / T_tr at T0/3", "",
             "The event engine also runs from further independent states (seeds 2, 3, ...); the standard "
             "deviation of R at T0/3 over all its states is the scatter of a single run.", "",
             "The checked rows compare each soft engine with the event engine at that engine's beta0; the other "
             "rows, with the other soft model's beta0, are listed for the discussion below.", "",
             "| mu | soft engine | event engine's beta0 | R soft at T0/3 | R event engine, same state | s.d. of one hard run | "
             "soft / hard - 1 |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        sd = "-" if r.get("R_hard_sd") is None else f"{r['R_hard_sd']:.4f}"
        which = f"{r['beta0']:.4f} ({'its own, checked' if r['checked'] else 'the other model' + chr(39) + 's'})"
        lines.append(f"| {r['mu']} | {NAMES[r['soft']]} | {which} | {r['R_soft']:.4f} | {r['R_hard']:.4f} | {sd} | "
                     f"{100 * r['diff']:+.2f}% |")
    lines += ["", "## All runs", "", "R where T_tr crosses T0/3 (or at the end if it does not): the runs last until the "
              "slower-cooling beta0 reaches T0/3 in the Walton theory.", "",
              "| mu | engine | beta0 | T_tr / T0 at the end | R at T0/3 | R at the end | Walton theory R at the end | "
              "CPU s per unit time |", "|---|---|---|---|---|---|---|---|"]
    for mu, per in data["results"].items():
        for name, r in per.items():
            if name == "times":
                continue
            th = f"{r['Trot_theory'][-1] / r['T_theory'][-1]:.4f}" if "T_theory" in r else "-"
            lines.append(f"| {mu} | {name} | {r['beta0']:.4f} | {r['T'][-1] / r['T'][0]:.4f} | {ratio_at_third(r):.4f} | "
                         f"{r['Trot'][-1] / r['T'][-1]:.4f} | {th} | {r['cpu'] / r['sim_time']:.3g} |")
    lines += ["", "![T_tr and T_rot of every engine](rough_cooling_soft_T.png)", "", "## Verdict", ""]
    if data["failures"]:
        lines += [f"Differences beyond {100 * TOL:g}% (exit status 1):", ""] + [f"* {f}" for f in data["failures"]]
    else:
        lines += [f"R at T0/3 agrees within {100 * TOL:g}% between the hard and the soft engines (exit status 0)."]
    lines += ["", "## Differences", ""]
    b = s["beta0"]
    lines.append(f"* The linear contact with kt = 2/7 kn sticks for half a tangential period (omega_t = sqrt(kn/meff)), "
                 f"so beta0 = {b['lammps']:.4f}: a sticking contact reverses the tangential contact velocity, and "
                 "Walton's rule with this beta0 stands for the soft contact (a contact that reaches mu |F_n| within "
                 "its duration slides there, as Walton's rule slides when the sticking impulse exceeds mu J_n).")
    if b["liggghts"] < 0:
        lines.append(f"* LIGGGHTS's Hertz-Mindlin contact has a tangential stiffness 8 G* sqrt(Reff delta), "
                     "2 (1 - nu) / (2 - nu) = 0.82 times the normal force's tangent stiffness 2 Y* sqrt(Reff delta) at "
                     "nu = 0.3, so its tangential oscillation (mass meff q / (1 + q)) is about 1.7 times faster than "
                     "the normal one and a sticking contact goes through nearly a whole tangential period: the "
                     f"measured beta0 = {b['liggghts']:.4f}, almost smooth. The soft contact's tangential force still reaches mu |F_n| within the contact and "
                     "slides there, transferring energy between translation and rotation, which Walton's rule "
                     "(one impulse compared with mu J_n, with (1 + beta0) close to 0 the sticking impulse is "
                     "almost never large enough to slide) cannot represent. The hard engines with this beta0 are "
                     "nearly smooth spheres, and their R differs from LIGGGHTS's by far more than 5%: not an engine's "
                     "error but the limit of Walton's model for a contact whose tangential period is shorter than "
                     "its duration. The rows with the linear contact's beta0 show how far LIGGGHTS's contact is from a "
                     "sticking limit near 1 instead: where most contacts slide (small mu) the sticking limit matters "
                     "little.")
    return "\n".join(lines)
