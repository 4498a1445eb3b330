#!/usr/bin/env python3
"""Cooling of a dilute granular gas in every engine against Haff's law.

  python3 -m compare.cooling [--quick] --out DIR [--build BUILD_DIR] [--keep]

One state (packing fraction 0.05, T0 = 1, unit spheres; `hardsphere run --write-data`, then an
elastic event-engine run) cools with normal restitution e, no friction, no gravity, in a periodic
box, in: the stepper and the event engine (`hardsphere run --restitution e`, TC model at its
default), Debian's LAMMPS with the linear spring-dashpot `gran/hooke kn 0 gamman 0 0 0`
(reference_inputs/lammps/in.granular_cooling, gamman from gamman_for_restitution) and LIGGGHTS's
hertz model with `coefficientRestitution e` (reference_inputs/liggghts/in.granular_cooling). The
soft spheres have the stiffness whose Barker-Henderson shift of a unit pair at T = 1 is `shift`
(as in the cross-validation) and dt = contact time / 80 (Hertz: at relative speed 6); 80 rather
than the elastic cross-validation's 20 because the damping force does not vanish at zero overlap,
which makes the integrator's error in e first order in dt (the two-sphere check below).

Haff's law: T(t) = T0 / (1 + (1 - e^2) Gamma0 t / 6)^2, Gamma0 the Enskog collision rate per
particle at T0, 4 n sigma^2 g(sigma) sqrt(pi T0 / m) with Carnahan-Starling's g. T = sum m v^2 / 3N
is measured at 20 times up to the time where Haff's law gives T0/3. A soft contact lasts t_c, so
soft spheres are expected to follow it only up to O(t_c Gamma0) (listed in the report). The event
engine also cools 8 further independent states: their mean is the hard-sphere curve without one
state's fluctuations, their standard deviation the scatter of a single run.

Writes DIR/cooling.json, DIR/cooling.md, DIR/cooling_T.png and DIR/cooling_speed.png. Exit status
1 when, before T0/3, a hard-sphere engine deviates from Haff's law (max over the measured times of
|T/T_Haff - 1|) by more than the ensemble allows (its largest |mean| + 4 s.d. over those times), a
soft engine by 2% more than that, or a two-sphere run of a soft
engine at the cooling run's stiffness and time step leaves with a normal speed ratio more than 1%
from e. --quick: N = 1000, e = 0.9, soft shift 0.01, under a minute. Full: N = 8000, e = 0.9 and
0.7, shift 0.0025 (docs/reports/validation/cooling.md).
"""
import argparse
import json
import math
import shlex
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from compare import hard_sphere_theory as hs_theory  # noqa: E402
from compare import soft_spheres as soft  # noqa: E402
from compare.crossval import plan as xv_plan  # noqa: E402
from compare.crossval import states as xv_states  # noqa: E402
from compare.crossval.engines import ROOT, Engines, find_tools, run_logged  # noqa: E402
from compare.crossval.observables import read_frames  # noqa: E402
from compare.crossval.report import fmt, table, versions  # noqa: E402
from compare.lammps_files import read_data, spheres, write_data  # noqa: E402

INPUTS = ROOT / "reference_inputs"
PHI = 0.05
MONO = [(1.0, 1.0, 1.0)]  # (number fraction, diameter, mass)
MEFF = 0.5  # reduced mass of two unit spheres
FRAMES = 20  # measured times after t = 0
ENSEMBLE = 8  # further states through the event engine, for the scatter of one run
LAST_FRACTION = 1 / 3  # measure until Haff's T reaches T0 / 3
EQUILIBRATE = 2.0  # elastic event-engine run making the state
STEPPER_DT = xv_plan.DEFAULT_DT  # the largest stepper dt (frame_dt)
# The damping force -meff gamman v_n does not vanish at delta = 0, so a contact's force jumps on
# and off within a step and velocity Verlet errs at first order, ~gamman dt, in e (20 steps per
# contact, the elastic cross-validation's choice, misses e = 0.7 by up to 3%; 80 by < 0.7%).
STEPS_PER_CONTACT = 80
SOFT_ENGINES = ("lammps hooke", "liggghts hertz")
ENGINES = ("stepper", "event") + SOFT_ENGINES
NAMES = {"stepper": "stepper", "event": "event engine", "lammps hooke": "LAMMPS gran/hooke",
         "liggghts hertz": "LIGGGHTS hertz"}
# Hard engines: the ensemble's measured scatter (SIGMAS s.d. of one run) around its mean departure
# from Haff's law; soft engines SOFT_MODEL more (O(t_c Gamma0) and their restitution error).
TOLERANCES = dict(sigmas=4.0, soft_model=0.02, pair_restitution=0.01)
PAIR_SPEEDS = (0.3, 1.5, 5.0)  # relative normal speeds of the two-sphere check
PAIR_PHASES = tuple((k + 0.5) / 8 for k in range(8))  # where in a step each contact starts


@dataclass
class Mode:
    name: str
    n: int
    restitutions: tuple
    shift: float  # Barker-Henderson shift of a unit pair at T = 1 (soft stiffness)


QUICK = Mode("quick", 1000, (0.9,), 0.01)
FULL = Mode("full", 8000, (0.9, 0.7), 0.0025)


# --- theory ----------------------------------------------------------------------------------

def gamman_for_restitution(e, kn, meff):
    """LAMMPS gran/hooke gamman (1/time) that gives restitution e: the head-on contact is
    delta'' + gamman delta' + (kn/meff) delta = 0, e = exp(-gamman t_c / 2) with
    t_c = pi / sqrt(kn/meff - gamman^2/4), so gamman = 2 |ln e| sqrt(kn/meff) / sqrt(pi^2 + ln^2 e)."""
    if not 0 < e <= 1:
        raise ValueError(f"restitution must be in (0, 1], not {e}")
    le = math.log(e)
    return -2.0 * le * math.sqrt(kn / meff) / math.sqrt(math.pi**2 + le * le)


def hooke_contact_time(gamman, kn, meff):
    """Duration of a damped linear contact, delta = 0 to delta = 0: pi / sqrt(kn/meff - gamman^2/4)."""
    return math.pi / math.sqrt(kn / meff - gamman * gamman / 4.0)


def hooke_restitution(gamman, kn, meff):
    """Restitution of the linear spring-dashpot: exp(-gamman t_c / 2)."""
    return math.exp(-gamman * hooke_contact_time(gamman, kn, meff) / 2.0)


def enskog_rate(phi, t0, mass=1.0):
    """Gamma0 = 4 n sigma^2 g(sigma) sqrt(pi T0 / m) of unit spheres (Carnahan-Starling g)."""
    return hs_theory.enskog_rate(phi, [(1.0, 1.0, mass)], kT=t0)


def haff_temperature(t, t0, e, gamma0):
    """Haff's law T0 / (1 + (1 - e^2) Gamma0 t / 6)^2 (t may be an array)."""
    return t0 / (1.0 + (1.0 - e * e) * gamma0 * np.asarray(t, dtype=float) / 6.0) ** 2


def haff_time(fraction, e, gamma0):
    """Time at which Haff's law reaches T = fraction T0 (e < 1)."""
    return (1.0 / math.sqrt(fraction) - 1.0) * 6.0 / ((1.0 - e * e) * gamma0)


def temperature(frame, mass):
    """sum m v^2 / (3N) of a frame (the velocities' frame; the states have zero momentum)."""
    return float((mass * (frame["vel"] ** 2).sum(axis=1)).sum() / (3 * len(mass)))


def haff_deviation(times, temps, t0, e, gamma0):
    """T / T_Haff - 1 at each time, and the largest |T / T_Haff - 1| with its time."""
    rel = np.asarray(temps) / haff_temperature(times, t0, e, gamma0) - 1.0
    k = int(np.argmax(np.abs(rel)))
    return rel, float(abs(rel[k])), float(times[k])


def frame_dt(t_end, dt_max):
    """The largest time step <= dt_max with a whole number of steps between the FRAMES equally
    spaced measuring times up to t_end, so every engine measures at t_end k / FRAMES."""
    interval = t_end / FRAMES
    return interval / math.ceil(interval / dt_max * (1 - 1e-12))


# --- soft-sphere settings --------------------------------------------------------------------

def mean_relative_speed(t0, meff=MEFF):
    """<|v_i - v_j|> of a Maxwellian pair: sqrt(8 T / (pi meff))."""
    return math.sqrt(8.0 * t0 / (math.pi * meff))


def soft_settings(engine, shift, e, t0, t_end):
    """Stiffness, time step (for measuring times up to t_end), input variables and contact times of
    a soft engine."""
    stiffness = xv_plan.stiffness_for_shift(engine, shift)
    dt = frame_dt(t_end, xv_plan.contact_time(engine, stiffness) / STEPS_PER_CONTACT)  # Hertz: at speed 6
    if engine == "lammps hooke":
        gamman = gamman_for_restitution(e, stiffness, MEFF)
        variables = dict(kn=stiffness, gamman=gamman)
        t_c = hooke_contact_time(gamman, stiffness, MEFF)
    else:
        gamman = None
        variables = dict(ymod=stiffness, restitution=e, ntypes=1)
        k = soft.hertz_stiffness("hertz_liggghts", stiffness, 0.25, soft.POISSON_LIGGGHTS)
        t_c = soft.contact_time_hertz(k, MEFF, mean_relative_speed(t0))  # elastic, at the mean speed
    return dict(engine=engine, shift=shift, stiffness=stiffness, dt=dt, gamman=gamman, variables=variables,
                contact_time=t_c, steps_per_contact=STEPS_PER_CONTACT)


def soft_script(engine):
    if engine == "lammps hooke":
        return INPUTS / "lammps" / "in.granular_cooling"
    return INPUTS / "liggghts" / "in.granular_cooling"


def soft_exe(engines, engine):
    return engines.lmp if engine == "lammps hooke" else engines.liggghts


# --- runs --------------------------------------------------------------------------------------

def run_stepper(engines, state, work, e, t_end):
    work.mkdir(parents=True, exist_ok=True)
    dt = frame_dt(t_end, STEPPER_DT)
    every = round(t_end / FRAMES / dt)
    run_logged([engines.hs, "run", "--read-data", state, "--restitution", e, "--dt", repr(dt),
          "--steps", every * FRAMES, "--dump", work / "run.dump", "--dump-every", every, "--json",
          work / "run.json"], work, work / "run.log")
    j = json.loads((work / "run.json").read_text())
    return dict(frames=read_frames(work / "run.dump", dt=dt), cpu_seconds=j["loop_cpu_seconds"],
                sim_time=j["sim_time"], settings=dict(dt=dt, contact_time_tc_model=j["contact_time"]),
                collisions=j["collisions"])


def run_event(engines, state, work, e, t_end):
    work.mkdir(parents=True, exist_ok=True)
    run_logged([engines.hs, "run", "--engine", "event", "--read-data", state, "--restitution", e, "--time", t_end,
          "--blocks", FRAMES, "--dump", work / "run.dump", "--json", work / "run.json"], work, work / "run.log")
    j = json.loads((work / "run.json").read_text())
    times = [k * t_end / FRAMES for k in range(FRAMES + 1)]
    return dict(frames=read_frames(work / "run.dump", times=times), cpu_seconds=j["loop_cpu_seconds"],
                sim_time=j["sim_time"], settings=dict(contact_time_tc_model=j["contact_time"]),
                collisions=j["collisions"])


def run_soft(engines, engine, state, work, settings, t_end):
    dt = settings["dt"]
    every = round(t_end / FRAMES / dt)
    r = engines.lammps_family(soft_exe(engines, engine), soft_script(engine), state, work, 1, dt, every * FRAMES,
                               0, every, every, contactsteps=1, extra=settings["variables"])
    return dict(frames=r["frames"], cpu_seconds=r["cpu_seconds"], sim_time=r["sim_time"],
                settings={k: v for k, v in settings.items() if k != "variables"}, collisions=None)


def write_pairs(path, pairs, box):
    """A data file with head-on pairs of unit spheres along x, one per (relative speed, gap), on a
    grid in y and z 6 diameters apart (box >= 6 sqrt(len(pairs)))."""
    side = math.ceil(math.sqrt(len(pairs)))
    atoms = []
    for k, (v, gap) in enumerate(pairs):
        y, z = 6.0 * (k % side) + 3.0, 6.0 * (k // side) + 3.0
        atoms += [(box / 2 - 0.5 - gap / 2, y, z, v / 2, 0.0, 0.0), (box / 2 + 0.5 + gap / 2, y, z, -v / 2, 0.0, 0.0)]
    atoms = np.array(atoms)
    # atom_style sphere/granular Velocities rows need the angular velocity too: zero
    write_data(path, spheres(atoms[:, :3], atoms[:, 3:], box=((0.0, box),) * 3, omega=0.0, title="head-on pairs"))


def pair_restitution(engines, engine, settings, e, work):
    """Head-on pairs through the soft engine at the cooling run's stiffness and time step, at each
    relative speed of PAIR_SPEEDS and PAIR_PHASES (the fraction of a step by which the first
    overlapping step follows the touch): exit over entry normal speed per pair."""
    work.mkdir(parents=True, exist_ok=True)
    dt = settings["dt"]
    if engine == "lammps hooke":
        longest = settings["contact_time"]
    else:
        k = soft.hertz_stiffness("hertz_liggghts", settings["stiffness"], 0.25, soft.POISSON_LIGGGHTS)
        longest = soft.contact_time_hertz(k, MEFF, min(PAIR_SPEEDS) * e)  # the slow end of the contact
    nrun = int(4 + 2.0 * longest / dt) + 20
    cases = [(v, p) for v in PAIR_SPEEDS for p in PAIR_PHASES]
    side = math.ceil(math.sqrt(len(cases)))
    write_pairs(work / "pairs.data", [(v, (3 + 1 - p) * v * dt) for v, p in cases], box=6.0 * side)
    r = engines.lammps_family(soft_exe(engines, engine), soft_script(engine), work / "pairs.data", work, 1, dt,
                               nrun, 0, nrun, nrun, contactsteps=1, extra=settings["variables"])
    first, last = r["frames"][0], r["frames"][-1]
    out = []
    for k, (v, phase) in enumerate(cases):
        a, b = 2 * k, 2 * k + 1
        if last["pos"][b, 0] - last["pos"][a, 0] <= 1.0:
            raise RuntimeError(f"{engine}: the pair at speed {v} is still in contact after {nrun} steps")
        v_in = first["vel"][a, 0] - first["vel"][b, 0]
        v_out = last["vel"][b, 0] - last["vel"][a, 0]
        out.append(dict(speed=v, phase=phase, restitution=v_out / v_in, rel_error=v_out / v_in / e - 1.0))
    return out


def pair_summary(pairs):
    """Per relative speed: mean and largest |relative error| of the restitution over the phases."""
    out = []
    for v in sorted({p["speed"] for p in pairs}):
        errs = np.array([p["rel_error"] for p in pairs if p["speed"] == v])
        out.append(dict(speed=v, mean_rel_error=float(errs.mean()), max_abs_rel_error=float(np.abs(errs).max())))
    return out


# --- the comparison --------------------------------------------------------------------------

def make_state(tools, directory, n, seed=1):
    """The state's data file (made in directory), its packing fraction and temperature."""
    path = xv_states.make_state(tools["hardsphere"], tools["lmp"], directory, n, PHI, "mono", EQUILIBRATE, seed=seed,
                                log=lambda _: None)
    s = read_data(path)
    phi = float((4.0 / 3.0 * math.pi * s.radius ** 3).sum() / s.volume)
    t0 = float((s.mass * (s.vel ** 2).sum(axis=1)).sum() / (3 * len(s)))
    return path, phi, t0


def ensemble(engines, tools, work, n, e, t_end):
    """The event engine from ENSEMBLE further independent states (seeds 2, 3, ...): the mean and
    standard deviation over the states of T/T_Haff - 1 at each measured time, i.e. the hard-sphere
    curve without one state's fluctuations, and the scatter of a single run."""
    rels = []
    for seed in range(2, 2 + ENSEMBLE):
        state, phi, t0 = make_state(tools, work / f"states_seed{seed}", n, seed)
        run = run_event(engines, state, work / f"ensemble_seed{seed}", e, t_end)
        r = summarise(run, xv_states.masses(state), t0, e, enskog_rate(phi, t0))
        rels.append(r["rel_deviation"])
    rels = np.array(rels)
    return dict(seeds=list(range(2, 2 + ENSEMBLE)), times=r["times"], mean=rels.mean(axis=0).tolist(),
                std=rels.std(axis=0, ddof=1).tolist(), runs=rels.tolist())


def cool(engines, engine, state, work, e, t_end, settings):
    if engine == "stepper":
        return run_stepper(engines, state, work, e, t_end)
    if engine == "event":
        return run_event(engines, state, work, e, t_end)
    return run_soft(engines, engine, state, work, settings, t_end)


def summarise(run, mass, t0, e, gamma0):
    times = np.array([f["t"] for f in run["frames"]])
    temps = np.array([temperature(f, mass) for f in run["frames"]])
    rel, worst, at = haff_deviation(times, temps, t0, e, gamma0)
    cpu_per_time = run["cpu_seconds"] / run["sim_time"]
    return dict(times=times.tolist(), T=temps.tolist(), T_haff=haff_temperature(times, t0, e, gamma0).tolist(),
                rel_deviation=rel.tolist(), max_abs_deviation=worst, max_at_time=at, cpu_seconds=run["cpu_seconds"],
                sim_time=run["sim_time"], cpu_seconds_per_unit_time=cpu_per_time, collisions=run["collisions"],
                settings=run["settings"])


def engine_tolerance(ens, engine):
    """Allowed max |T/T_Haff - 1| for an engine: the ensemble's largest |mean| + SIGMAS s.d. over the
    measured times (plus SOFT_MODEL for a soft engine)."""
    hard = max(abs(m) + TOLERANCES["sigmas"] * s for m, s in zip(ens["mean"], ens["std"]))
    return hard + (TOLERANCES["soft_model"] if engine in SOFT_ENGINES else 0.0)


def check(results, pair_checks, ensembles):
    failures = []
    for e, per_engine in results.items():
        for engine, r in per_engine.items():
            tol = engine_tolerance(ensembles[e], engine)
            if r["max_abs_deviation"] > tol:
                failures.append(f"e = {e}, {NAMES[engine]}: max |T/T_Haff - 1| = {r['max_abs_deviation']:.4f} "
                                f"> {tol:.4f} (at t = {r['max_at_time']:.3g})")
    for e, per_engine in pair_checks.items():
        for engine, pairs in per_engine.items():
            for p in pairs:
                if abs(p["rel_error"]) > TOLERANCES["pair_restitution"]:
                    failures.append(f"e = {e}, {NAMES[engine]}: two-sphere restitution {p['restitution']:.5f} at "
                                    f"speed {p['speed']} is {p['rel_error']:+.2%} from e")
    return failures


# --- report ----------------------------------------------------------------------------------

STYLE = {"stepper": ("C0", "o"), "event": ("C1", "s"), "lammps hooke": ("C2", "^"), "liggghts hertz": ("C3", "v")}


def fig_temperature(out, results, ensembles, t0, gamma0):
    es = list(results)
    fig, axes = plt.subplots(2, len(es), figsize=(5.2 * len(es), 6.4), squeeze=False,
                             gridspec_kw=dict(height_ratios=(2.2, 1.2)), sharex="col")
    for col, e in enumerate(es):
        top, bottom = axes[0, col], axes[1, col]
        t_end = max(max(r["times"]) for r in results[e].values())
        t = np.linspace(0, t_end, 200)
        top.plot(t, haff_temperature(t, t0, float(e), gamma0) / t0, "k-", lw=1.5, label="Haff (Enskog rate)")
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


def result_rows(per_engine, ens):
    base = per_engine.get("stepper")
    rows = []
    for engine, r in per_engine.items():
        tol = engine_tolerance(ens, engine)
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


def write_markdown(out, data, figs, command):
    s = data["settings"]
    lines = [
        "# Cooling of a dilute granular gas: Haff's law in every engine", "",
        f"Generated by `{command}` ({s['mode']} mode) in {data['run_seconds']:.0f} s on "
        f"{data['machine']['machine']}; hardsphere {data['machine']['hardsphere']}, LAMMPS "
        f"{data['machine']['lammps']}, {data['machine']['liggghts']}.", "",
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
        f"the ensemble's largest |mean| + {TOLERANCES['sigmas']:g} s.d. over those times, for soft engines "
        f"{100 * TOLERANCES['soft_model']:g}% more; the two-sphere restitution "
        f"within {100 * TOLERANCES['pair_restitution']:g}% of e. The ensemble: the event engine from "
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
                        result_rows(per_engine, data["ensemble"][e]))]
    lines += [f"![T(t) against Haff's law]({figs[0]})", "", f"![CPU time per unit simulated time]({figs[1]})", "",
              "## Verdict", ""]
    if data["failures"]:
        lines += ["Disagreements (exit status 1):", ""] + [f"* {f}" for f in data["failures"]]
    else:
        lines += ["Every engine is within its tolerance (exit status 0)."]
    lines += ["", "## Differences", ""] + [f"* {n}" for n in data["notes"]] + [""]
    (out / "cooling.md").write_text("\n".join(lines))


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


def relative_command(argv):
    words = ["python3", "-m", "compare.cooling"]
    for w in argv:
        p = Path(w)
        if p.is_absolute() and ROOT in p.resolve().parents:
            w = str(p.resolve().relative_to(ROOT))
        words.append(w)
    return " ".join(shlex.quote(w) for w in words)


# --- main ------------------------------------------------------------------------------------

def run_all(tools, mode, work, log=print):
    engines = Engines(str(tools["hardsphere"]), None, tools["lmp"], tools["liggghts"], tools["mpirun"])
    state, phi, t0 = make_state(tools, work / "states", mode.n)
    gamma0 = enskog_rate(phi, t0)
    mass = xv_states.masses(state)
    results, pair_checks, soft_by_e, t_end, ensembles = {}, {}, {}, {}, {}
    for e in mode.restitutions:
        key = f"{e:g}"
        t_end[key] = haff_time(LAST_FRACTION, e, gamma0)
        soft_by_e[key] = {g: soft_settings(g, mode.shift, e, t0, t_end[key]) for g in SOFT_ENGINES}
        pair_checks[key] = {}
        for g in SOFT_ENGINES:
            pair_checks[key][g] = pair_restitution(engines, g, soft_by_e[key][g], e, work / f"pairs_e{key}_{g[:3]}")
            worst = max(abs(p["rel_error"]) for p in pair_checks[key][g])
            log(f"e = {key}, {NAMES[g]}: two-sphere restitution within {100 * worst:.3f}% of e "
                f"({len(pair_checks[key][g])} pairs)")
        t = time.time()
        ensembles[key] = ens = ensemble(engines, tools, work, mode.n, e, t_end[key])
        log(f"e = {key}, event engine over {ENSEMBLE} further states: T/T_Haff - 1 at T0/3 = "
            f"{100 * ens['mean'][-1]:+.2f}% +- {100 * ens['std'][-1]:.2f}% (s.d.) ({time.time() - t:.0f} s)")
        results[key] = {}
        for g in ENGINES:
            t = time.time()
            run = cool(engines, g, state, work / f"e{key}_{g.replace(' ', '_')}", e, t_end[key],
                       soft_by_e[key].get(g))
            results[key][g] = r = summarise(run, mass, t0, e, gamma0)
            log(f"e = {key}, {NAMES[g]}: max |T/T_Haff - 1| = {100 * r['max_abs_deviation']:.2f}%, "
                f"{r['cpu_seconds_per_unit_time']:.3g} CPU s per unit time ({time.time() - t:.0f} s)")
    settings = dict(mode=mode.name, n=mode.n, phi=phi, T0=t0, gamma0=gamma0,
                    g_contact=hs_theory.contact_value(phi, MONO, 0, 0), restitutions=list(mode.restitutions),
                    t_end=t_end, frames=FRAMES, last_fraction=LAST_FRACTION, equilibrate=EQUILIBRATE,
                    stepper_dt=STEPPER_DT, soft_shift=mode.shift, steps_per_contact=STEPS_PER_CONTACT,
                    pair_speeds=list(PAIR_SPEEDS), pair_phases=list(PAIR_PHASES), ensemble_states=ENSEMBLE,
                    tolerances=TOLERANCES)
    soft_json = {e: {g: {k: v for k, v in s.items() if k != "variables"} for g, s in per.items()}
                 for e, per in soft_by_e.items()}
    return dict(settings=settings, soft_settings=soft_json, pair_checks=pair_checks, results=results,
                ensemble=ensembles)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="N = 1000, e = 0.9, under a minute")
    ap.add_argument("--build", default=str(ROOT / "build"), help="build directory (default: build)")
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--keep", action="store_true", help="keep the runs (DIR/cooling_runs)")
    a = ap.parse_args(argv)
    t_start = time.time()
    out = Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    tools = find_tools(a.build)
    missing = [k for k in ("lmp", "liggghts") if not tools[k]]
    if missing:
        sys.exit(f"cooling: missing {', '.join(missing)} (scripts/setup.sh installs them)")
    mode = QUICK if a.quick else FULL
    log = lambda s: print(f"[{time.time() - t_start:6.0f} s] {s}", flush=True)  # noqa: E731
    if a.keep:
        work = out / "cooling_runs"
        work.mkdir(exist_ok=True)
        data = run_all(tools, mode, work, log)
    else:
        with tempfile.TemporaryDirectory(prefix="cooling_") as d:
            data = run_all(tools, mode, Path(d), log)
    data["failures"] = check(data["results"], data["pair_checks"], data["ensemble"])
    data["machine"] = versions(tools)
    data["notes"] = notes(data)
    data["run_seconds"] = time.time() - t_start
    data["command"] = relative_command(argv)
    figs = fig_temperature(out, data["results"], data["ensemble"], data["settings"]["T0"],
                           data["settings"]["gamma0"]), \
        fig_speed(out, data["results"], data["settings"])
    (out / "cooling.json").write_text(json.dumps(data, indent=1, default=float) + "\n")
    write_markdown(out, data, figs, data["command"])
    print(f"cooling: {len(data['failures'])} disagreements; report in {out / 'cooling.md'}")
    for f in data["failures"]:
        print("  DISAGREE: " + f)
    return 1 if data["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())
