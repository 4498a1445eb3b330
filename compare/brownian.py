#!/usr/bin/python3
"""Brownian motion of one big, heavy sphere in a hard-sphere gas against kinetic theory.

  python3 -m compare.brownian [--quick] --out DIR [--build DIR] [--hardsphere PATH] [--work DIR]
      [--event-time T] [--stepper-time T] [--jobs J]

One big sphere (id 1, diameter D_big, mass M) among small unit spheres (diameter 1, mass 1) at packing
fraction phi in a periodic cube (compare.big_sphere_scene), kT from the state's energy. Both engines
(`hardsphere run --engine stepper|event`) follow it with the tracker (`--track 1 --track-every dt_s
--track-file`): unwrapped position, velocity and its pair-collision count. From the tracks:

- D: from the mean-squared displacement, D = [MSD(t2) - MSD(t1)] / (6 (t2 - t1)) with t1 = 3 tau,
  t2 = 8 tau (tau = M D_E / kT, Enskog's velocity relaxation time; divided by the 1% an exponential
  velocity memory still takes off the slope there), per block of 30 tau of each independent run; D and
  its error are the mean and standard error over all blocks of all runs.
- Enskog's heavy-tracer value D_E = 3 kT / (8 n sigma12^2 g12 sqrt(2 pi mu kT)), n the small-sphere number
  density, mu = M m / (M + m), sigma12 = (D_big + 1) / 2, g12 the BMCSL contact value (compare.hard_sphere_theory),
  and its closure-free form D_E,cf = 3 kT / (4 mu Gamma12) with Gamma12 the big sphere's measured collision
  rate. The total momentum is zero, so the big sphere moves in the centre-of-mass frame of M_tot = M + N m:
  its displacement is (1 - M/M_tot) times its displacement relative to the gas, and the expected value is
  D_exp = (1 - M/M_tot)^2 D_E,cf.
- Equipartition: <M V^2>/3 against kT (1 - M / M_tot) (T_big_ratio, error over blocks).
- A sweep over density and size (event engine; figure only): D against Enskog and against slip
  Stokes-Einstein with the finite-box correction, D_SE = kT / (4 pi eta R) - kT xi / (6 pi eta L),
  R = sigma12, xi = 2.837297, eta Enskog's shear viscosity of the small-sphere fluid.

Writes DIR/brownian.json, DIR/brownian.md, DIR/brownian_path.png, DIR/brownian_msd_vacf.png and (full mode)
DIR/brownian_sweep.png. Exit status 1 when an engine's D differs from D_exp by more than
max(3 sigma, 10%), its T_big_ratio differs from 1 by more than 3 sigma, or its collision rate Gamma12
differs from Enskog's (BMCSL g12) by more than max(3 sigma, 2%) (--quick: 4 sigma). The 10%
allow for the heavy-tracer corrections Enskog's first Sonine value leaves out: of order sqrt(m/M) (0.09 at
M/m = 125) and from correlated (ring) collisions.
The validation point is phi 0.01 (mean free path 11.8, four times sigma12): from phi 0.1 on (mean free
path below sigma12 = 3) the measured D exceeds Enskog's clearly (the sweep shows it), as correlated
collisions and the gas's backflow come in once the big sphere is not small against the mean free path.
--quick: D_big 5, M 125, phi 0.01, 1000 small spheres, 4 runs per engine, each run one block, no sweep.
Full (docs/reports/validation/brownian.md): 2000 small spheres, 144 event runs and 24 stepper runs of 7000,
and the sweep.
"""
import json
import math
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from compare import big_sphere_scene, harness
from compare import hard_sphere_theory as hs_theory
from compare.brownian_figures import plot_msd_vacf, plot_path, plot_sweep

SAMPLE_EVERY = 0.5  # tracker interval (a whole number of stepper steps)
STEPPER_DT = 0.05
EQUILIBRATE = 20.0
BLOCK_TAUS = 30.0  # block length in Enskog relaxation times
LAG_TAUS = (3.0, 8.0)  # MSD slope between these lags
TOLERANCE = 0.10  # allowed relative departure of D from D_exp beyond the statistical error


def make_state(path, n_small, phi, d_big, m_big, seed):
    scene = big_sphere_scene.make_scene(n_small, phi, big=1, big_diameter=d_big, big_mass=m_big, seed=seed)
    big_sphere_scene.write_scene(path, scene, "brownian: one big sphere in a hard-sphere gas")
    v2 = (scene["mass"][:, None] * scene["vel"] ** 2).sum()
    kT = v2 / (3 * (len(scene["mass"]) - 1))  # zero total momentum: 3(N - 1) degrees of freedom
    return scene["box"], kT


def run_track(exe, data, engine, duration, workdir, tag):
    track = Path(workdir) / f"{tag}.track"
    summary = Path(workdir) / f"{tag}.json"
    cmd = [exe, "run", "--read-data", str(data), "--time", repr(duration), "--equilibrate-time", repr(EQUILIBRATE),
           "--track", "1", "--track-every", repr(SAMPLE_EVERY), "--track-file", str(track), "--json", str(summary),
           "--quiet"]
    if engine == "event":
        cmd += ["--engine", "event", "--blocks", "1"]
    else:
        # Sweep detection: overlap detection (auto's choice at this dt) misses grazes, ~0.4% of the collisions.
        cmd += ["--dt", repr(STEPPER_DT), "--detect", "sweep"]
    harness.run_program(cmd)
    shown = ["hardsphere" if c == exe else Path(c).name if c.startswith(str(workdir)) else c for c in cmd]
    return dict(rows=np.loadtxt(track, comments="#", ndmin=2), summary=json.loads(summary.read_text()),
                command=" ".join(shown))


def msd_at(r, lag):
    d = r[lag:] - r[:-lag]
    return float(np.mean((d * d).sum(axis=1)))


def analyse(runs, m_big, kT, th, whole_runs=False):
    """D, Gamma12 and the kinetic temperature per block of every run (whole_runs: one block per run),
    then means and standard errors."""
    tau = th["tau"]
    block = max(int(round(BLOCK_TAUS * tau / SAMPLE_EVERY)), 8)
    if whole_runs:
        block = min(len(r["rows"]) for r in runs) - 1
    l1, l2 = (max(1, int(round(x * tau / SAMPLE_EVERY))) for x in LAG_TAUS)
    l2 = min(l2, block // 2)
    l1 = min(l1, l2 - 1)
    # The slope between the lags falls short of D by what is left of the velocity memory, about
    # tau (e^(-t1/tau) - e^(-t2/tau)) / (t2 - t1) for an exponential memory (1% at 3 and 8 tau).
    t1, t2 = l1 * SAMPLE_EVERY, l2 * SAMPLE_EVERY
    remainder = 1 - tau * (math.exp(-t1 / tau) - math.exp(-t2 / tau)) / (t2 - t1)
    d_b, g_b, t_b = [], [], []
    t_factor = 1 - m_big / (m_big + th["n_small"])
    for run in runs:
        rows = run["rows"]
        for s in range(0, len(rows) - block, block):  # whole blocks only
            b = rows[s:s + block + 1]
            r, v, c = b[:, 1:4], b[:, 4:7], b[:, 7]
            d_b.append((msd_at(r, l2) - msd_at(r, l1)) / (6 * (l2 - l1) * SAMPLE_EVERY) / remainder)
            g_b.append((c[-1] - c[0]) / (b[-1, 0] - b[0, 0]))
            # Each state has its own kT (energy is conserved exactly): the ratio is taken per run.
            t_b.append(m_big * float(np.mean((v * v).sum(axis=1))) / 3 / (run["kT"] * t_factor))

    def mean_err(x):
        x = np.asarray(x)
        return float(x.mean()), float(x.std(ddof=1) / math.sqrt(len(x))) if len(x) > 1 else float("nan")

    D, D_err = mean_err(d_b)
    G, G_err = mean_err(g_b)
    ratio, ratio_err = mean_err(t_b)
    mu = th["mu"]
    t_expected = kT * t_factor
    d_cf = 3 * kT / (4 * mu * G)
    d_exp = th["momentum_factor"] * d_cf
    return dict(D=D, D_err=D_err, D_enskog=th["D_enskog"], D_enskog_closure_free=d_cf,
                D_enskog_closure_free_err=d_cf * G_err / G, D_expected=d_exp, momentum_factor=th["momentum_factor"],
                D_over_expected=D / d_exp, Gamma12=G, Gamma12_err=G_err, Gamma12_enskog=th["Gamma12_enskog"],
                g12=th["g12"], g12_measured=th["g12"] * G / th["Gamma12_enskog"], T_big=ratio * t_expected,
                T_big_err=ratio_err * t_expected, T_big_expected=t_expected, T_big_ratio=ratio,
                T_big_ratio_err=ratio_err,
                kT=kT, tau=tau, blocks=len(d_b), block_time=block * SAMPLE_EVERY, runs=len(runs),
                run_time=float(runs[0]["rows"][-1, 0]), lags=[l1 * SAMPLE_EVERY, l2 * SAMPLE_EVERY],
                cpu_seconds=sum(r["summary"]["loop_cpu_seconds"] for r in runs))


def curves(runs, tau):
    """MSD at log-spaced lags and the normalised velocity autocorrelation, averaged over runs."""
    n = min(len(r["rows"]) for r in runs)
    lags = np.unique(np.round(np.logspace(0, math.log10(max(2, min(n // 4, 40 * tau / SAMPLE_EVERY))), 40)))
    lags = lags.astype(int)
    msd = np.mean([[msd_at(r["rows"][:, 1:4], k) for k in lags] for r in runs], axis=0)
    kmax = min(n // 2, int(6 * tau / SAMPLE_EVERY) + 1)
    acf = np.zeros(kmax)
    for r in runs:
        v = r["rows"][:, 4:7]
        f = np.fft.rfft(v, n=2 * len(v), axis=0)
        c = np.fft.irfft((f * f.conj()).real, axis=0)[:kmax].sum(axis=1)
        acf += c / (len(v) - np.arange(kmax))
    acf /= len(runs)
    return lags * SAMPLE_EVERY, msd, np.arange(kmax) * SAMPLE_EVERY, acf / acf[0], acf


def measure(exe, engines, n_small, phi, d_big, m_big, seeds, workdir, jobs, whole_runs=False):
    """engines: {name: run time per seed}. Returns per engine the analysis, curves and runs."""
    states = {}
    for s in seeds:
        data = Path(workdir) / f"state_{phi}_{d_big}_{s}.data"
        states[s] = (data, *make_state(data, n_small, phi, d_big, m_big, s))
    length = states[seeds[0]][1]
    tasks = [(eng, s) for eng, (t, k) in engines.items() for s in seeds[:k]]
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        futs = {task: pool.submit(run_track, exe, states[task[1]][0], task[0], engines[task[0]][0], workdir,
                                  f"{task[0]}_{phi}_{d_big}_{task[1]}") for task in tasks}
        done = {task: f.result() for task, f in futs.items()}
    out = {}
    for eng in engines:
        runs = [done[t] for t in tasks if t[0] == eng]
        for t, r in zip((t for t in tasks if t[0] == eng), runs):
            r["kT"] = states[t[1]][2]
        kT = float(np.mean([r["kT"] for r in runs]))
        th = hs_theory.heavy_tracer(phi, n_small, d_big, m_big, length, kT)
        th["n_small"] = n_small
        res = analyse(runs, m_big, kT, th, whole_runs)
        res.update(phi=phi, D_big=d_big, M=m_big, n_small=n_small, box=length,
                   D_stokes_einstein=th["D_stokes_einstein"], eta=th["eta"], command=runs[0]["command"])
        cv = curves(runs, th["tau"])
        # Green-Kubo cross-check: D = (1/3) integral of <V(0).V(t)> up to 6 tau (no error bar).
        res["D_green_kubo"] = float(np.trapz(cv[4], cv[2]) / 3)
        out[eng] = dict(result=res, curves=cv, runs=runs)
    return out


def verdict(res, sigmas):
    """D against D_exp, the kinetic temperature against equipartition, and the big sphere's collision rate
    against Enskog's (BMCSL g12; the sharpest check at short runs, within sigmas or 2%)."""
    d_ok = abs(res["D"] - res["D_expected"]) <= max(sigmas * res["D_err"], TOLERANCE * res["D_expected"])
    t_ok = abs(res["T_big_ratio"] - 1) <= sigmas * res["T_big_ratio_err"]
    g_ok = abs(res["Gamma12"] - res["Gamma12_enskog"]) <= max(sigmas * res["Gamma12_err"], 0.02 * res["Gamma12_enskog"])
    return d_ok, t_ok, g_ok


def fmt(x, e=None, digits=4):
    if e is None:
        return f"{x:.{digits}g}"
    return f"{x:.{digits}g} ± {e:.2g}"


def report(session, out, val, sweep, params, sigmas, failures):
    """Writes DIR/brownian.md and DIR/brownian.json; returns the markdown's path."""
    head = val["event"]["result"]
    keys = ("D", "D_err", "D_enskog", "D_enskog_closure_free", "D_expected", "T_big_ratio", "T_big_ratio_err")
    js = {"headline_engine": "event", **{k: head[k] for k in keys}, "parameters": params,
          "engines": {e: v["result"] for e, v in val.items()}, "sweep": sweep, "seconds": round(session.seconds),
          "tolerance": TOLERANCE, "sigmas": sigmas, "pass": not failures, "command": session.command}
    p = params
    lines = ["# Brownian motion of a heavy sphere against kinetic theory", "", session.generated(), "",
             f"One big sphere (diameter {p['D_big']:g}, mass {p['M']:g}, M/m = {p['M']:g}) among {p['n_small']} unit "
             f"spheres at packing fraction {p['phi']:g} in a periodic box of {head['box']:.4g}; kT = {head['kT']:.4f} "
             "from the states' energies. `--quick` is the ctest `brownian_quick`.", "",
             "Each run: `" + head["command"] + "` (stepper: `--dt 0.05 --detect sweep` instead of the event options). "
             f"D from the MSD slope between lags {head['lags'][0]:g} and {head['lags'][1]:g} (3 and 8 Enskog "
             f"relaxation times tau = {head['tau']:.3g}; divided by the ~1% an exponential memory still takes off "
             f"the slope) within blocks of {head['block_time']:g} time units; errors are standard errors over all "
             "blocks of all independent runs. The Green-Kubo integral of the velocity autocorrelation up to 6 tau "
             f"gives D = {head['D_green_kubo']:.4g} (event engine, no error bar).", "",
             "| engine | runs x time | blocks | D | D_E (BMCSL g12) | D_E closure-free | D_exp = (1-M/M_tot)^2 D_E,cf "
             "| D / D_exp | Gamma12 (Enskog) | T_big ratio | pass |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for eng, v in val.items():
        r = v["result"]
        ok = all(verdict(r, sigmas))
        lines.append(f"| {eng} | {r['runs']} x {r['run_time']:g} | {r['blocks']} | {fmt(r['D'], r['D_err'])} | "
                     f"{fmt(r['D_enskog'])} | {fmt(r['D_enskog_closure_free'], r['D_enskog_closure_free_err'])} | "
                     f"{fmt(r['D_expected'])} | {fmt(r['D_over_expected'], r['D_err'] / r['D_expected'], 3)} | "
                     f"{fmt(r['Gamma12'], r['Gamma12_err'])} ({fmt(r['Gamma12_enskog'])}) | "
                     f"{fmt(r['T_big_ratio'], r['T_big_ratio_err'])} | {'yes' if ok else 'NO'} |")
    lines += ["", f"Pass: |D - D_exp| <= max({sigmas:g} sigma, {TOLERANCE:.0%} D_exp), |T_big ratio - 1| <= "
              f"{sigmas:g} sigma and |Gamma12 - Enskog's| <= max({sigmas:g} sigma, 2%). Expected: the heavy-tracer Enskog value holds up to corrections of order "
              f"sqrt(m/M) = {1 / math.sqrt(p['M']):.3f} and from correlated (ring) collisions; the factor "
              f"(1 - M/M_tot)^2 = {head['momentum_factor']:.4f} is the zero-total-momentum frame (the big sphere's "
              "displacement is 1 - M/M_tot of its displacement relative to the gas). Not in D_exp: the periodic "
              "box's hydrodynamic correction kT xi / (6 pi eta L), which would lower D by "
              f"{head['kT'] * 2.837297 / (6 * math.pi * head['eta'] * head['box']) / head['D_expected']:.1%} of "
              "D_exp if the gas were hydrodynamic on the box's scale. g12 from the measured "
              f"collision rate: {head['g12_measured']:.4f} (BMCSL {head['g12']:.4f}).", "",
             "![path of the big sphere](brownian_path.png)", "",
             "![MSD and velocity autocorrelation](brownian_msd_vacf.png)", ""]
    if sweep:
        lines += ["## Sweep over density and size (event engine, figure only)", "",
                  "| phi | D_big | M | mean free path / sigma12 | D | D_exp (Enskog) | D_SE (slip, finite box) "
                  "| D / D_exp |",
                  "|---|---|---|---|---|---|---|---|"]
        for s in sweep:
            knudsen = hs_theory.free_path(s["n_small"] / s["box"] ** 3) / (0.5 * (s["D_big"] + 1))
            lines.append(f"| {s['phi']:g} | {s['D_big']:g} | {s['M']:g} | {knudsen:.2g} | {fmt(s['D'], s['D_err'])} | "
                         f"{fmt(s['D_expected'])} | {fmt(s['D_stokes_einstein'])} | "
                         f"{fmt(s['D'] / s['D_expected'], s['D_err'] / s['D_expected'], 3)} |")
        lines += ["", "Slip Stokes-Einstein: D_SE = kT / (4 pi eta sigma12) - kT xi / (6 pi eta L), xi = 2.837297 "
                  "(Yeh-Hummer / Hasimoto), eta Enskog's shear viscosity of the small-sphere fluid. Enskog's heavy-tracer "
                  "value assumes uncorrelated collisions, the limit of a big sphere small against the gas's mean "
                  "free path 1 / (sqrt(2) pi n) (a Knudsen number mean free path / sigma12 well above 1). As that "
                  "ratio falls towards and below 1, correlated collisions and the gas's backflow carry the big "
                  "sphere further than Enskog's value; in the dense gas D lies between Enskog's value and slip "
                  "Stokes-Einstein's, the hydrodynamic limit.", "",
                  "![D against density and size](brownian_sweep.png)", ""]
    if failures:
        lines += ["**Failed:** " + "; ".join(failures), ""]
    return session.write_report(out, "brownian", "\n".join(lines), js)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--event-time", type=float, help="event-engine time per run (full 7000, quick 4000)")
    ap.add_argument("--event-runs", type=int, help="independent event-engine runs (full 144, quick 4)")
    ap.add_argument("--stepper-time", type=float, help="stepper time per run (full 7000, quick 3000)")
    ap.add_argument("--stepper-runs", type=int, help="independent stepper runs (full 24, quick 4)")
    ap.add_argument("--no-sweep", action="store_true", help="skip the density and size sweep")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once (2)")
    a = ap.parse_args(argv)
    session = harness.Session("compare.brownian", a, argv)
    exe = harness.tools(a, need=("hardsphere",))["hardsphere"]
    out = session.out()
    if a.quick:
        params = dict(n_small=1000, phi=0.01, D_big=5.0, M=125.0)
        ev, er, st, sr, sigmas = 4000.0, 4, 3000.0, 4, 4.0
    else:
        params = dict(n_small=2000, phi=0.01, D_big=5.0, M=125.0)
        ev, er, st, sr, sigmas = 7000.0, 144, 7000.0, 24, 3.0
    ev, er = a.event_time or ev, a.event_runs or er
    st, sr = a.stepper_time or st, a.stepper_runs or sr
    params.update(event_time=ev, event_runs=er, stepper_time=st, stepper_runs=sr, sample_every=SAMPLE_EVERY,
                  stepper_dt=STEPPER_DT, equilibrate_time=EQUILIBRATE)
    seeds = list(range(1, max(er, sr) + 1))
    sweep = []
    with session.workdir() as work:
        val = measure(exe, {"event": (ev, er), "stepper": (st, sr)}, params["n_small"], params["phi"],
                      params["D_big"], params["M"], seeds, work, a.jobs, whole_runs=a.quick)
        if not a.quick and not a.no_sweep:
            # About 2000 spheres at every point; the time per run scales with the relaxation time.
            for d_big, m_big in ((5.0, 125.0), (3.0, 27.0)):
                for phi in (0.01, 0.05, 0.1, 0.2, 0.3):
                    if (d_big, m_big, phi) == (params["D_big"], params["M"], params["phi"]):
                        sweep.append(val["event"]["result"])
                        continue
                    length = (2000 * math.pi / 6 / phi) ** (1 / 3)
                    tau = hs_theory.heavy_tracer(phi, 2000, d_big, m_big, length, 1.0)["tau"]
                    n_small = 2000
                    r = measure(exe, {"event": (max(200.0, 160 * tau), 4)}, n_small, phi, d_big, m_big, [1, 2, 3, 4],
                                work, a.jobs)
                    sweep.append(r["event"]["result"])
    failures = []
    for eng, v in val.items():
        d_ok, t_ok, g_ok = verdict(v["result"], sigmas)
        r = v["result"]
        if not g_ok:
            failures.append(f"{eng}: Gamma12 {r['Gamma12']:.4g} +- {r['Gamma12_err']:.2g} against Enskog's "
                            f"{r['Gamma12_enskog']:.4g}")
        if not d_ok:
            failures.append(f"{eng}: D {r['D']:.4g} +- {r['D_err']:.2g} against D_exp {r['D_expected']:.4g}")
        if not t_ok:
            failures.append(f"{eng}: T_big ratio {r['T_big_ratio']:.4f} +- {r['T_big_ratio_err']:.2g}")
    first = val["event"]["runs"][0]["rows"]
    plot_path(first, out / "brownian_path.png",
              f"Big sphere (D {params['D_big']:g}, M {params['M']:g}) in a gas at phi {params['phi']:g}: "
              f"unwrapped path over time {first[-1, 0]:g} (event engine, one run), projections")
    plot_msd_vacf(val, out / "brownian_msd_vacf.png", params["M"])
    if sweep:
        plot_sweep(sweep, out / "brownian_sweep.png")
    path = report(session, out, val, sweep, params, sigmas, failures)
    for eng, v in val.items():
        r = v["result"]
        session.log(f"{eng}: D {r['D']:.4g} +- {r['D_err']:.2g} (D_exp {r['D_expected']:.4g}, D_E {r['D_enskog']:.4g}, "
              f"closure-free {r['D_enskog_closure_free']:.4g}), T_big ratio {r['T_big_ratio']:.4f} +- "
              f"{r['T_big_ratio_err']:.2g}, {r['blocks']} blocks")
    return session.finish(failures, path)


if __name__ == "__main__":
    harness.main(main)
