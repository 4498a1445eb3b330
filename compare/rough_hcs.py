#!/usr/bin/python3
"""Homogeneous cooling of rough inelastic hard spheres in both engines against kinetic theory.

  python3 -m compare.rough_hcs --out DIR [--quick] [--build DIR] [--hardsphere PATH] [--work DIR]

A dilute gas (phi 0.05, unit spheres, T0 = 1; `hardsphere run --write-data` and an elastic smooth
event-engine run of 2 time units, as compare.cooling makes its state) gets angular velocities
drawn from Maxwell-Boltzmann at T_rot0 = R0 T0 (each component normal with variance T_rot0 / I,
I = 0.4 m (d/2)^2) and cools with normal restitution e and tangential restitution beta (or Walton's
friction mu with the sticking limit beta0) in the event engine and the stepper (dt 0.01). T_tr and
T_rot are measured from the dumps' v and w at 20 equal intervals up to the time where the theory
gives T_tr = T0/3.

Theory (compare/rough_theory.py, derived there from the collision rule and checked by a Monte
Carlo of it in tests/compare/test_rough_theory.py): Huthmann and Zippelius (1997) and Luding et
al. (1998), molecular chaos with Maxwellian v and w and the Enskog collision frequency
omega = 4 n d^2 chi sqrt(pi T / m), chi = (1 - phi/2) / (1 - phi)^3:
    dT/dt = -(4/3) omega (A T - B T_rot),  dT_rot/dt = (4/3) omega (B T - C T_rot),
    eta = q (1 + beta) / (2 (1 + q)), A = (1 - e^2)/4 + eta (1 - eta), B = eta^2 / q,
    C = (eta / q)(1 - eta / q),  R = T_rot / T of the scaling state: B R^2 + (C - A) R - B = 0.
Walton's friction: the same closure evaluated by a Monte Carlo of the Walton rule (no closed form
between its limits); its asymptotes (McNamara and Luding 1998) are every contact sliding (small mu,
closed form in rough_theory.sliding_rates) and every contact sticking (large mu: constant beta0).

Two runs per case and engine and seed: from R0 = 1 (the two-temperature transient: T_tr(t) and
T_rot(t) against the ODEs) and from R0 = the theory's R (the scaling state: R measured over the
frames of the second half). Sonine level: the comparison is with the Maxwellian (zeroth Sonine)
theory; the first Sonine correction of Santos, Kremer and dos Santos (2011) to R is evaluated with
the cumulants a20, a02, a11 measured in the scaling runs (rough_theory.energy_changes with their
weights) and listed, so the report shows where it matters.

Writes DIR/rough_hcs.json, DIR/rough_hcs.md, DIR/rough_hcs_T.png and DIR/rough_hcs_R.png. Exit
status 1 if, for any case and engine, the seed mean of R differs from the theory by more than 3%
plus 4 standard errors, or T_tr / T_theory - 1 (seed mean, max over the measured times) by more
than 3% plus 4 standard errors. --quick: two cases, 2000 spheres, about a minute on 2 cores
(the ctest rough_hcs_quick). The report's text and figures: compare.rough_hcs_report.
"""
import json
import math
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from compare import harness
from compare import rough_theory as rt
from compare.lammps_files import read_data, read_dump, spheres, write_data
from compare.rough_hcs_report import fig_ratio, fig_temperatures, markdown

PHI = 0.05
Q = 0.4
FRAMES = 20
LAST_FRACTION = 1 / 3
EQUILIBRATE = 2.0
STEPPER_DT = 0.01
TOL = 0.03  # relative, on R and on T_tr, plus SIGMAS standard errors of the seed mean
SIGMAS = 4
THEORY_SAMPLES = 400000  # Monte Carlo samples of the Walton and Sonine rates


@dataclass(frozen=True)
class Case:
    e: float
    beta: float  # beta, or Walton's beta0 with a finite mu
    mu: float = math.inf
    label: str = ""

    @property
    def key(self):
        return f"e{self.e:g}_b{self.beta:g}" + ("" if math.isinf(self.mu) else f"_mu{self.mu:g}")

    @property
    def walton(self):
        return math.isfinite(self.mu)


CASES = (Case(0.9, 0.0), Case(0.9, 0.5), Case(0.7, 0.5), Case(0.95, -0.5),
         Case(0.98, 0.5, 0.03, "small mu: contacts slide"), Case(0.9, 0.5, 0.3, "intermediate mu"),
         Case(0.9, 0.5, 10.0, "large mu: contacts stick"))
QUICK_CASES = (Case(0.9, 0.5), Case(0.95, -0.5))


@dataclass
class Mode:
    name: str
    n: int
    seeds: int
    cases: tuple
    engines: tuple
    sonine: bool  # evaluate the first Sonine correction (a Monte Carlo of a minute per case)


QUICK = Mode("quick", 2000, 4, QUICK_CASES, ("event", "stepper"), False)
FULL = Mode("full", 8000, 4, CASES, ("event", "stepper"), True)


# --- theory per case ---------------------------------------------------------------------------

def theory_rates(case):
    """(h, tabulated h for the ODEs, its description)."""
    if not case.walton:
        h = rt.constant_beta_rates(case.e, case.beta, Q)
        return h, h
    h = rt.sampled_rates(case.e, case.beta, Q, case.mu, samples=THEORY_SAMPLES)
    return h, rt.tabulated(h, 0.02, 3.0, 40)


def theory(case):
    h, h_ode = theory_rates(case)
    out = dict(R=rt.ratio_of_rates(h) if case.walton else rt.scaling_ratio(case.e, case.beta, Q))
    if case.walton:
        out["R_sliding"] = rt.ratio_of_rates(rt.sliding_rates(case.e, case.mu, Q))
        out["R_sticking"] = rt.scaling_ratio(case.e, case.beta, Q)
    return out, h_ode


def sonine_ratio(case, cumulants):
    """R with the first Sonine correction for the measured cumulants, as the exact Maxwellian R
    times the Monte Carlo's corrected over Maxwellian ratio (the same samples for both)."""
    plain = rt.ratio_of_rates(rt.sampled_rates(case.e, case.beta, Q, case.mu, samples=THEORY_SAMPLES), 0.02, 5.0, 16)
    corrected = rt.ratio_of_rates(rt.sampled_rates(case.e, case.beta, Q, case.mu, samples=THEORY_SAMPLES,
                                                   cumulants=cumulants), 0.02, 5.0, 16)
    if plain is None or corrected is None:
        return None
    return corrected / plain


# --- runs --------------------------------------------------------------------------------------

def make_state(hs, work, n, seed):
    """An equilibrated smooth state (positions and velocities), cached per seed."""
    final = work / f"state_n{n}_s{seed}.data"
    if not final.exists():
        raw = work / f"raw_n{n}_s{seed}.data"
        harness.run_program([hs, "run", "--n", n, "--phi", PHI, "--seed", seed, "--steps", 0, "--write-data", raw], work)
        harness.run_program([hs, "run", "--engine", "event", "--read-data", raw, "--time", EQUILIBRATE, "--blocks", 1,
             "--write-data", final], work)
    return final


def spin_state(state, path, r0, seed):
    """The state with angular velocities from Maxwell-Boltzmann at T_rot0 = r0 T0 (T0 the state's)."""
    s = read_data(state)
    t0 = rt.temperatures_of(s.vel, np.zeros_like(s.vel), s.mass, np.ones(len(s)))[0]
    inertia = Q * s.mass * s.radius ** 2
    rng = np.random.default_rng(1000 + seed)
    omega = rng.normal(size=(len(s), 3)) * np.sqrt(r0 * t0 / inertia)[:, None]
    write_data(path, spheres(s.pos, s.vel, box=s.box, diameter=s.diameter, mass=s.mass, omega=omega,
                             title="rough cooling state"))
    return t0


def physics_args(case):
    args = ["--restitution", case.e, "--tangential-restitution", case.beta]
    if case.walton:
        args += ["--friction", case.mu]
    return args


def cool(hs, engine, data, work, case, t_end):
    """T_tr, T_rot and the cumulants at FRAMES + 1 equal times up to t_end."""
    dump, js = work / f"{data.stem}_{engine}.dump", work / f"{data.stem}_{engine}.json"
    if engine == "event":
        cmd = [hs, "run", "--engine", "event", "--read-data", data, "--time", repr(t_end), "--blocks", FRAMES]
    else:
        interval = t_end / FRAMES
        dt = interval / math.ceil(interval / STEPPER_DT * (1 - 1e-12))
        every = round(interval / dt)
        cmd = [hs, "run", "--read-data", data, "--dt", repr(dt), "--steps", every * FRAMES, "--dump-every", every]
    harness.run_program(cmd + physics_args(case) + ["--dump", dump, "--json", js, "--quiet"], work)
    s = read_data(data)
    inertia = Q * s.mass * s.radius ** 2
    rows = []
    for f in read_dump(dump):
        vel = np.stack([f["vx"], f["vy"], f["vz"]], axis=1)
        omega = np.stack([f["wx"], f["wy"], f["wz"]], axis=1)
        rows.append(rt.temperatures_of(vel, omega, s.mass, inertia) + rt.cumulants_of(vel, omega, s.mass, inertia))
    j = json.loads(js.read_text())
    dump.unlink()
    rows = np.array(rows)
    if len(rows) != FRAMES + 1:
        raise RuntimeError(f"{dump}: {len(rows)} frames, expected {FRAMES + 1}")
    return dict(T=rows[:, 0], Trot=rows[:, 1], cumulants=rows[:, 2:5], cpu=j.get("loop_cpu_seconds"),
                collisions=j.get("collisions"), json=j)


def mean_err(values):
    values = np.asarray(values, dtype=float)
    err = values.std(axis=0, ddof=1) / math.sqrt(len(values)) if len(values) > 1 else np.full(values.shape[1:], np.nan)
    return values.mean(axis=0), err


def measure_case(hs, work, mode, case, log):
    th, h_ode = theory(case)
    t0_nominal = 1.0
    t_end = rt.time_to_fraction(LAST_FRACTION, PHI, t0_nominal, 1.0, h_ode)
    times = np.linspace(0.0, t_end, FRAMES + 1)
    result = dict(case=dict(e=case.e, beta=case.beta, mu=None if not case.walton else case.mu, label=case.label),
                  theory=th, t_end=t_end, times=times.tolist(), engines={})
    r_star = th["R"] if th["R"] is not None else 1.0
    def one_seed(engine, seed):
        state = make_state(hs, work, mode.n, seed)
        # transient from T_rot0 = T0
        d1 = work / f"{case.key}_s{seed}_r1_{engine}.data"
        t0 = spin_state(state, d1, 1.0, seed)
        c = cool(hs, engine, d1, work, case, t_end * t0 ** -0.5)
        tt, tr = rt.temperatures(times * t0 ** -0.5, PHI, c["T"][0], c["Trot"][0] / c["T"][0], h_ode)
        # scaling state from T_rot0 = R T0
        d2 = work / f"{case.key}_s{seed}_rs_{engine}.data"
        spin_state(state, d2, r_star, seed)
        c2 = cool(hs, engine, d2, work, case, t_end * t0 ** -0.5)
        half = slice(FRAMES // 2, None)
        return dict(rel_t=c["T"] / tt - 1.0, rel_rot=c["Trot"] / tr - 1.0,
                    curve=dict(T=(c["T"] / t0).tolist(), Trot=(c["Trot"] / t0).tolist(), T_theory=(tt / t0).tolist(),
                               Trot_theory=(tr / t0).tolist()),
                    cpu=(c["cpu"] or 0.0), sim=t_end * t0 ** -0.5,
                    ratio=float(np.mean(c2["Trot"][half] / c2["T"][half])), cumulants=c2["cumulants"][half].mean(axis=0))

    for seed in range(1, mode.seeds + 1):
        make_state(hs, work, mode.n, seed)
    for engine in mode.engines:
        # two runs at a time: the machine's two cores
        with ThreadPoolExecutor(max_workers=2) as pool:
            per_seed = list(pool.map(lambda sd: one_seed(engine, sd), range(1, mode.seeds + 1)))
        rel_t = [x["rel_t"] for x in per_seed]
        rel_rot = [x["rel_rot"] for x in per_seed]
        curves = [x["curve"] for x in per_seed]
        ratios = [x["ratio"] for x in per_seed]
        cums = [x["cumulants"] for x in per_seed]
        cpu, sim = sum(x["cpu"] for x in per_seed), sum(x["sim"] for x in per_seed)
        mt, et = mean_err(rel_t)
        mr, er = mean_err(rel_rot)
        rm, re_ = mean_err(np.array(ratios)[:, None])
        cm, ce = mean_err(cums)
        k = int(np.argmax(np.abs(mt)))  # the largest deviation, listed
        excess = float(np.max(np.abs(mt) - SIGMAS * et))  # the check: beyond SIGMAS standard errors
        result["engines"][engine] = dict(
            T_rel_mean=mt.tolist(), T_rel_err=et.tolist(), Trot_rel_mean=mr.tolist(), Trot_rel_err=er.tolist(),
            T_worst=float(mt[k]), T_worst_err=float(et[k]), T_worst_time=float(times[k]), T_excess=excess,
            Trot_max=float(np.max(np.abs(mr))),
            R=float(rm[0]), R_err=float(re_[0]), R_seeds=ratios, cumulants=cm.tolist(), cumulants_err=ce.tolist(),
            curves=curves[:1], cpu_seconds_per_unit_time=cpu / sim if sim else None)
        log(f"{case.key} {engine}: R {rm[0]:.4f} +- {re_[0]:.4f} (theory {th['R']}), "
            f"max T_tr/T_th - 1 {100 * mt[k]:+.2f}% +- {100 * et[k]:.2f}%")
    cm = np.mean([r["cumulants"] for r in result["engines"].values()], axis=0)
    result["sonine_factor"] = sonine_ratio(case, tuple(cm)) if th["R"] is not None and mode.sonine else None
    return result


def check(results):
    failures = []
    for r in results:
        th = r["theory"]["R"]
        for engine, m in r["engines"].items():
            name = f"{r['key']} {engine}"
            if th is not None and abs(m["R"] / th - 1) > TOL + SIGMAS * m["R_err"] / th:
                failures.append(f"{name}: R = {m['R']:.4f} +- {m['R_err']:.4f}, theory {th:.4f}")
            if m["T_excess"] > TOL:
                failures.append(f"{name}: T_tr / T_theory - 1 = {m['T_worst']:+.4f} +- {m['T_worst_err']:.4f} at "
                                f"t = {m['T_worst_time']:.3g}")
    return failures


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("--quick", action="store_true", help="two cases, 2000 spheres, 4 seeds (about a minute)")
    a = ap.parse_args(argv)
    session = harness.Session("compare.rough_hcs", a, argv)
    hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
    out = session.out()
    mode = QUICK if a.quick else FULL
    results = []
    with session.workdir() as work:
        for case in mode.cases:
            r = measure_case(hs, work, mode, case, session.log)
            r["key"] = case.key
            results.append(r)
    data = dict(settings=dict(mode=mode.name, n=mode.n, seeds=mode.seeds, phi=PHI, inertia=Q, frames=FRAMES,
                              stepper_dt=STEPPER_DT, tolerance=TOL, sigmas=SIGMAS, equilibrate=EQUILIBRATE),
                results=results, command=session.command)
    data["failures"] = check(results)
    data["seconds"] = session.seconds
    fig_temperatures(out, results)
    fig_ratio(out, results, Q)
    report = session.write_report(out, "rough_hcs", markdown(data, session.generated(extra=f" ({mode.name} mode)")),
                                  data)
    return session.finish(data["failures"], report)


if __name__ == "__main__":
    harness.main(main)
