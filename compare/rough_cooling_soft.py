#!/usr/bin/python3
"""Cooling of a rough granular gas: the hard-sphere engines with Walton's friction against LAMMPS
and LIGGGHTS frictional soft spheres from the same state.

  python3 -m compare.rough_cooling_soft --out DIR [--quick] [--build DIR] [--hardsphere PATH] [--work DIR]

One state (phi 0.05, unit spheres, T0 = 1, T_rot0 = T0; compare.rough_hcs.make_state and
spin_state) cools with normal restitution e = 0.9 and Coulomb friction mu = 0.1 and 0.5 in:
  LAMMPS `pair_style granular`, `hooke kn gamman damping mass_velocity tangential linear_history
  kt 0 mu` (reference_inputs/lammps/in.rough_cooling; kt = 2/7 kn, no tangential damping, no
  rolling or twisting), gamman from compare.soft_spheres.gamman_for_restitution;
  LIGGGHTS `gran model hertz tangential history tangential_damping off` with coefficientRestitution
  e and coefficientFriction mu (reference_inputs/liggghts/in.rough_cooling);
  the event engine and the stepper with --restitution e --tangential-restitution beta0 --friction mu.
The soft stiffness is compare.cooling's (Barker-Henderson shift of a unit pair at T = 1), dt the
contact time / 80.

beta0 (Walton's sticking limit) of each soft model: a sticking contact's tangential relative
velocity of the contact points g_t evolves as an oscillator of mass m_t = meff q / (1 + q) on the
tangential spring, so at the end of the contact g_t' = cos(omega_t t_c) g_t, beta0 = -cos(omega_t
t_c). For the linear model omega_t = sqrt(kt (1 + q) / (q meff)) and t_c = pi / sqrt(kn/meff -
gamman^2/4); kt = 2/7 kn makes omega_t = sqrt(kn/meff) and beta0 = -cos(pi / sqrt(1 - ln^2 e /
(pi^2 + ln^2 e))) = 0.99998 at e = 0.9. For Hertz-Mindlin both stiffnesses grow as sqrt(delta) and
the history force is k_t(delta) times the accumulated displacement, with no closed form: beta0 is
measured, as for LAMMPS, by a two-sphere run of each soft input with mu = 1e6 (every contact
sticks): an oblique contact with a small tangential velocity, beta0 = -g_t' / g_t (the rule above
checked against it for LAMMPS).

Measured: T_tr and T_rot at 20 equal intervals up to the time where the hard-sphere Walton theory
(compare.rough_theory, Maxwellian closure) reaches T0/3; R = T_rot / T_tr at T0/3 of each soft
engine against the event engine's run with that soft engine's beta0; CPU seconds per unit
simulated time. Writes DIR/rough_cooling_soft.json, .md and rough_cooling_soft_T.png; exit status
1 if an R at T0/3 differs between the hard and soft engines by more than 5%.
--quick: N = 1000, one mu, shift 0.01.
"""
import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from compare import hard_sphere_theory as hs_theory
from compare import harness
from compare import rough_theory as rt
from compare import rough_hcs
from compare import soft_spheres as soft
from compare.crossval import plan as xv_plan
from compare.lammps_files import loop_times, read_data, read_dump, spheres, write_data
from compare.rough_cooling_soft_report import NAMES, SOFT, figure, markdown, ratio_at_third

ROOT = Path(__file__).resolve().parent.parent
INPUTS = ROOT / "reference_inputs"
E = 0.9
Q = 0.4
MEFF = 0.5
FRAMES = 20
STEPS_PER_CONTACT = 80
KT_OVER_KN = 2.0 / 7.0
TOL = 0.05
ENSEMBLE = 4  # further states through the event engine


@dataclass
class Mode:
    name: str
    n: int
    mus: tuple
    shift: float


QUICK = Mode("quick", 1000, (0.5,), 0.01)
FULL = Mode("full", 4000, (0.1, 0.5), 0.005)


def run(cmd, cwd):
    """Runs cmd in cwd (harness.run_program); its wall seconds."""
    t = time.time()
    harness.run_program(cmd, cwd=cwd)
    return time.time() - t


def settings(engine, shift):
    if engine == "lammps":
        kn = xv_plan.stiffness_for_shift("lammps hooke", shift)
        gamman = soft.gamman_for_restitution(E, kn, MEFF)
        t_c = soft.hooke_contact_time(gamman, kn, MEFF)
        return dict(kn=kn, gamman=gamman, kt=KT_OVER_KN * kn, dt=t_c / STEPS_PER_CONTACT, contact_time=t_c)
    ymod = xv_plan.stiffness_for_shift("liggghts hertz", shift)
    t_c = xv_plan.contact_time("liggghts hertz", ymod)  # at relative speed 6, the shortest that matters
    k = soft.hertz_stiffness("hertz_liggghts", ymod, 0.25, soft.POISSON_LIGGGHTS)
    return dict(ymod=ymod, restitution=E, dt=t_c / STEPS_PER_CONTACT,
                contact_time=soft.contact_time_hertz(k, MEFF, hs_theory.mean_relative_speed(1.0, MEFF)))


def beta0_linear(s):
    return soft.sticking_beta0(s["kt"], s["contact_time"], MEFF, Q)


def soft_run(engine, s, data, work, mu, nrun, every):
    variables = dict(data=Path(data).resolve(), mu=mu, dt=s["dt"], nrun=nrun, dumpevery=every, dumpfile="run.dump")
    if engine == "lammps":
        exe, script = "lmp", INPUTS / "lammps" / "in.rough_cooling"
        variables.update(kn=s["kn"], gamman=s["gamman"], kt=s["kt"])
    else:
        exe, script = "liggghts", INPUTS / "liggghts" / "in.rough_cooling"
        variables.update(ymod=s["ymod"], restitution=s["restitution"])
    work.mkdir(parents=True, exist_ok=True)
    cmd = [exe, "-in", script, "-log", "log.lammps", "-screen", "none"]
    for k, v in variables.items():
        cmd += ["-var", k, v]
    run(cmd, work)
    seconds = loop_times((work / "log.lammps").read_text())[-1][0]
    return list(read_dump(work / "run.dump")), seconds


def measure_beta0(engine, s, work):
    """Two unit spheres, oblique, relative normal speed 1 and tangential contact velocity 0.05,
    through the soft input with mu = 1e6: -g_t(after) / g_t(before)."""
    work.mkdir(parents=True, exist_ok=True)
    box = 10.0
    gap = 0.02
    pos = np.array([[5.0 - 0.5 - gap / 2, 5.0, 5.0], [5.0 + 0.5 + gap / 2, 5.0, 5.0]])
    vel = np.array([[0.5, 0.025, 0.0], [-0.5, -0.025, 0.0]])
    data = work / "pair.data"
    write_data(data, spheres(pos, vel, box=((0.0, box),) * 3, omega=0.0, title="oblique pair"))
    nrun = int((gap + 4 * s["contact_time"]) / s["dt"]) + 10
    frames, _ = soft_run(engine, s, data, work, 1e6, nrun, nrun)

    p0 = np.stack([frames[0]["xu"], frames[0]["yu"], frames[0]["zu"]], axis=1)
    # the normal of the first frame: the pair's line turns by ~ g_t t_c during the contact, but after
    # it by g_t t, which would leak the normal velocity into a later frame's tangential part
    n = (p0[0] - p0[1]) / np.linalg.norm(p0[0] - p0[1])

    def gt(f):
        v = np.stack([f["vx"], f["vy"], f["vz"]], axis=1)
        w = np.stack([f["omegax"], f["omegay"], f["omegaz"]], axis=1)
        g = v[0] - v[1] - 0.5 * np.cross(w[0] + w[1], n)
        return g - (g @ n) * n, -(g @ n)
    g0, _ = gt(frames[0])
    g1, _ = gt(frames[-1])
    return float(-(g1 @ g0) / (g0 @ g0))


def temps(frames, mass, inertia):
    out = []
    for f in frames:
        v = np.stack([f["vx"], f["vy"], f["vz"]], axis=1)
        w = np.stack([f["omegax"], f["omegay"], f["omegaz"]], axis=1) if "omegax" in f.names else \
            np.stack([f["wx"], f["wy"], f["wz"]], axis=1)
        out.append(rt.temperatures_of(v, w, mass, inertia))
    return np.array(out)


def hard_run(hs, engine, data, work, beta0, mu, t_end):
    js, dump = work / f"{engine}_{beta0:.4f}_{mu}.json", work / f"{engine}_{beta0:.4f}_{mu}.dump"
    phys = ["--restitution", E, "--tangential-restitution", repr(beta0), "--friction", mu]
    if engine == "event":
        cmd = [hs, "run", "--engine", "event", "--read-data", data, "--time", repr(t_end), "--blocks", FRAMES]
    else:
        interval = t_end / FRAMES
        dt = interval / math.ceil(interval / 0.01 * (1 - 1e-12))
        every = round(interval / dt)
        cmd = [hs, "run", "--read-data", data, "--dt", repr(dt), "--steps", every * FRAMES, "--dump-every", every]
    run(cmd + phys + ["--dump", dump, "--json", js, "--quiet"], work)
    frames = list(read_dump(dump))
    dump.unlink()
    return frames, json.loads(js.read_text())["loop_cpu_seconds"]


def run_all(hs, mode, work, log):
    state = rough_hcs.make_state(hs, work, mode.n, 1)
    data = work / "rough_state.data"
    t0 = rough_hcs.spin_state(state, data, 1.0, 1)
    s = read_data(data)
    inertia = Q * s.mass * s.radius ** 2
    phi = float((math.pi / 6 * s.diameter ** 3).sum() / np.prod(s.box[:, 1] - s.box[:, 0]))
    sets = {g: settings(g, mode.shift) for g in SOFT}
    beta0 = {}
    for g in SOFT:
        beta0[g] = measure_beta0(g, sets[g], work / f"pair_{g}")
        log(f"{g}: beta0 measured {beta0[g]:.5f}" + (f", rule {beta0_linear(sets[g]):.5f}" if g == "lammps" else ""))
    results = {}
    for mu in mode.mus:
        key = f"{mu:g}"
        results[key] = {}
        # long enough for the slower-cooling beta0 to reach T0/3
        h = rt.tabulated(rt.sampled_rates(E, min(beta0.values()), Q, mu, samples=200000), 0.02, 5.0, 30)
        t_end = rt.time_to_fraction(1 / 3, phi, t0, 1.0, h)
        times = np.linspace(0, t_end, FRAMES + 1)
        for g in SOFT:
            st = sets[g]
            every = max(1, round(t_end / FRAMES / st["dt"]))
            dt = t_end / FRAMES / every
            st = dict(st, dt=dt)
            t = time.time()
            frames, seconds = soft_run(g, st, data, work / f"mu{key}_{g}", mu, every * FRAMES, every)
            tt = temps(frames, s.mass, inertia)
            results[key][g] = dict(T=tt[:, 0].tolist(), Trot=tt[:, 1].tolist(), cpu=seconds, sim_time=t_end, dt=dt,
                                   beta0=beta0[g])
            log(f"mu {key} {g}: R(T0/3) {tt[-1, 1] / tt[-1, 0]:.4f} ({time.time() - t:.0f} s)")
        for b_name, b in beta0.items():
            h_b = rt.tabulated(rt.sampled_rates(E, b, Q, mu, samples=200000), 0.02, 5.0, 30)
            for engine in ("event", "stepper"):
                frames, seconds = hard_run(hs, engine, data, work, b, mu, t_end)
                tt = temps(frames, s.mass, inertia)
                ht, hr = rt.temperatures(times, phi, tt[0, 0], tt[0, 1] / tt[0, 0], h_b)
                results[key][f"{engine} beta0 {b_name}"] = dict(T=tt[:, 0].tolist(), Trot=tt[:, 1].tolist(), cpu=seconds,
                                                               sim_time=t_end, beta0=b, T_theory=ht.tolist(),
                                                               Trot_theory=hr.tolist())
                log(f"mu {key} {engine} beta0 {b:.4f}: R(T0/3) {tt[-1, 1] / tt[-1, 0]:.4f}, theory {hr[-1] / ht[-1]:.4f}")
            # the event engine from further states: the scatter of one run's R at T0/3
            spread = []
            for seed in range(2, 2 + ENSEMBLE):
                other = work / f"rough_state_s{seed}.data"
                rough_hcs.spin_state(rough_hcs.make_state(hs, work, mode.n, seed), other, 1.0, seed)
                frames, _ = hard_run(hs, "event", other, work, b, mu, t_end)
                tt = temps(frames, s.mass, inertia)
                spread.append(ratio_at_third(dict(T=tt[:, 0], Trot=tt[:, 1])))
            results[key][f"event beta0 {b_name}"]["R_other_states"] = spread
            log(f"mu {key} event beta0 {b:.4f}, {ENSEMBLE} other states: R(T0/3) {np.mean(spread):.4f} "
                f"s.d. {np.std(spread, ddof=1):.4f}")
        results[key]["times"] = times.tolist()
    return dict(settings=dict(mode=mode.name, n=mode.n, phi=phi, T0=t0, e=E, mus=list(mode.mus), shift=mode.shift,
                              steps_per_contact=STEPS_PER_CONTACT, kt_over_kn=KT_OVER_KN, soft=sets, tolerance=TOL,
                              beta0=beta0, beta0_rule_lammps=beta0_linear(sets["lammps"])), results=results)


def check(data):
    """R at T0/3 of each soft engine against the event engine with that engine's beta0 (the check)
    and with the other soft engine's beta0 (listed, not checked)."""
    failures, rows = [], []
    for mu, per in data["results"].items():
        for g in SOFT:
            for b_name in SOFT:
                hard = per[f"event beta0 {b_name}"]
                rs, rh = ratio_at_third(per[g]), ratio_at_third(hard)
                sd = float(np.std(hard["R_other_states"] + [rh], ddof=1)) if "R_other_states" in hard else None
                rows.append(dict(mu=mu, soft=g, beta0_of=b_name, beta0=hard["beta0"], R_soft=rs, R_hard=rh,
                                 diff=rs / rh - 1, R_hard_sd=sd, checked=b_name == g))
                if b_name == g and abs(rs / rh - 1) > TOL:
                    failures.append(f"mu {mu} {NAMES[g]}: R(T0/3) {rs:.4f} against the event engine's {rh:.4f} "
                                    f"(beta0 {hard['beta0']:.4f})")
    return failures, rows


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("--quick", action="store_true", help="N = 1000, one mu, shift 0.01")
    a = ap.parse_args(argv)
    session = harness.Session("compare.rough_cooling_soft", a, argv)
    tools = harness.tools(a, need=("hardsphere", "lmp", "liggghts"))
    out = session.out()
    mode = QUICK if a.quick else FULL
    with session.workdir() as work:
        data = run_all(tools["hardsphere"], mode, work, session.log)
    data["failures"], rows = check(data)
    data["rows"] = rows
    data["seconds"] = session.seconds
    figure(out, data)
    report = session.write_report(out, "rough_cooling_soft",
                                  markdown(data, rows, session.generated(extra=f" ({mode.name} mode)")), data)
    return session.finish(data["failures"], report)


if __name__ == "__main__":
    harness.main(main)
