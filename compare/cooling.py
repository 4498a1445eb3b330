#!/usr/bin/env python3
"""Cooling of a dilute granular gas in every engine against Haff's law.

  python3 -m compare.cooling [--quick] --out DIR [--build DIR] [--hardsphere PATH] [--work DIR]

One state (packing fraction 0.05, T0 = 1, unit spheres; `hardsphere run --write-data`, then an
elastic event-engine run) cools with normal restitution e, no friction, no gravity, in a periodic
box, in: the stepper and the event engine (`hardsphere run --restitution e`, TC model at its
default), Debian's LAMMPS with the linear spring-dashpot `gran/hooke kn 0 gamman 0 0 0`
(reference_inputs/lammps/in.granular_cooling, gamman from soft_spheres.gamman_for_restitution) and LIGGGHTS's
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
0.7, shift 0.0025 (docs/reports/validation/cooling.md). The runs: compare.cooling_runs; the
report's text and figures: compare.cooling_report; the formulas: compare.hard_sphere_theory and
compare.soft_spheres.
"""
import time
from dataclasses import dataclass

from compare import harness
from compare import hard_sphere_theory as hs_theory
from compare.cooling_report import fig_speed, fig_temperature, markdown, notes
from compare.cooling_runs import (ENGINES, ENSEMBLE, EQUILIBRATE, FRAMES, LAST_FRACTION, MONO, NAMES, PAIR_PHASES,
                                  PAIR_SPEEDS, SOFT_ENGINES, STEPPER_DT, STEPS_PER_CONTACT, cool, enskog_rate,
                                  engine_tolerance, ensemble, make_state, pair_restitution, soft_settings, summarise)
from compare.crossval import states as xv_states
from compare.crossval.engines import Engines
from compare.machine_info import versions

# Hard engines: the ensemble's measured scatter (sigmas s.d. of one run) around its mean departure
# from Haff's law; soft engines soft_model more (O(t_c Gamma0) and their restitution error).
TOLERANCES = dict(sigmas=4.0, soft_model=0.02, pair_restitution=0.01)


@dataclass
class Mode:
    name: str
    n: int
    restitutions: tuple
    shift: float  # Barker-Henderson shift of a unit pair at T = 1 (soft stiffness)


QUICK = Mode("quick", 1000, (0.9,), 0.01)
FULL = Mode("full", 8000, (0.9, 0.7), 0.0025)


def check(results, pair_checks, ensembles):
    failures = []
    for e, per_engine in results.items():
        for engine, r in per_engine.items():
            tol = engine_tolerance(ensembles[e], engine, TOLERANCES)
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


def run_all(tools, mode, work, log=print):
    engines = Engines(str(tools["hardsphere"]), None, tools["lmp"], tools["liggghts"], tools["mpirun"])
    state, phi, t0 = make_state(tools, work / "states", mode.n)
    gamma0 = enskog_rate(phi, t0)
    mass = xv_states.masses(state)
    results, pair_checks, soft_by_e, t_end, ensembles = {}, {}, {}, {}, {}
    for e in mode.restitutions:
        key = f"{e:g}"
        t_end[key] = hs_theory.haff_time(LAST_FRACTION, e, gamma0)
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
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("--quick", action="store_true", help="N = 1000, e = 0.9, under a minute")
    a = ap.parse_args(argv)
    session = harness.Session("compare.cooling", a, argv)
    tools = harness.tools(a, need=("hardsphere", "lmp", "liggghts"))
    out = session.out()
    mode = QUICK if a.quick else FULL
    with session.workdir() as work:
        data = run_all(tools, mode, work, session.log)
    data["failures"] = check(data["results"], data["pair_checks"], data["ensemble"])
    data["machine"] = versions(tools)
    data["notes"] = notes(data)
    data["run_seconds"] = session.seconds
    data["command"] = session.command
    figs = fig_temperature(out, data["results"], data["ensemble"], data["settings"]["T0"],
                           data["settings"]["gamma0"]), \
        fig_speed(out, data["results"], data["settings"])
    report = session.write_report(out, "cooling", markdown(data, figs, session.generated(
        data["machine"], f" ({mode.name} mode)")), data)
    return session.finish(data["failures"], report)


if __name__ == "__main__":
    harness.main(main)
