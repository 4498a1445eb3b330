"""The runs of compare.cooling: one engine's cooling run from a state, the event engine's ensemble of
further states, and the soft engines' two-sphere restitution check. The set-up's constants are
here; the comparison, its tolerances and the report are compare.cooling's."""
import json
import math

import numpy as np

from compare import hard_sphere_theory as hs_theory
from compare import soft_spheres as soft
from compare.crossval import plan as xv_plan
from compare.crossval import states as xv_states
from compare.crossval.engines import ROOT, run_logged
from compare.crossval.observables import read_frames
from compare.lammps_files import read_data, spheres, write_data

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
PAIR_SPEEDS = (0.3, 1.5, 5.0)  # relative normal speeds of the two-sphere check
PAIR_PHASES = tuple((k + 0.5) / 8 for k in range(8))  # where in a step each contact starts
SOFT_ENGINES = ("lammps hooke", "liggghts hertz")
ENGINES = ("stepper", "event") + SOFT_ENGINES
NAMES = {"stepper": "stepper", "event": "event engine", "lammps hooke": "LAMMPS gran/hooke",
         "liggghts hertz": "LIGGGHTS hertz"}


def enskog_rate(phi, t0, mass=1.0):
    """Gamma0 = 4 n sigma^2 g(sigma) sqrt(pi T0 / m) of unit spheres (Carnahan-Starling g)."""
    return hs_theory.enskog_rate(phi, [(1.0, 1.0, mass)], kT=t0)


def temperature(frame, mass):
    """sum m v^2 / (3N) of a frame (the velocities' frame; the states have zero momentum)."""
    return float((mass * (frame["vel"] ** 2).sum(axis=1)).sum() / (3 * len(mass)))


def haff_deviation(times, temps, t0, e, gamma0):
    """T / T_Haff - 1 at each time, and the largest |T / T_Haff - 1| with its time."""
    rel = np.asarray(temps) / hs_theory.haff_temperature(times, t0, e, gamma0) - 1.0
    k = int(np.argmax(np.abs(rel)))
    return rel, float(abs(rel[k])), float(times[k])


def frame_dt(t_end, dt_max):
    """The largest time step <= dt_max with a whole number of steps between the FRAMES equally
    spaced measuring times up to t_end, so every engine measures at t_end k / FRAMES."""
    interval = t_end / FRAMES
    return interval / math.ceil(interval / dt_max * (1 - 1e-12))


# --- soft-sphere settings --------------------------------------------------------------------

def soft_settings(engine, shift, e, t0, t_end):
    """Stiffness, time step (for measuring times up to t_end), input variables and contact times of
    a soft engine."""
    stiffness = xv_plan.stiffness_for_shift(engine, shift)
    dt = frame_dt(t_end, xv_plan.contact_time(engine, stiffness) / STEPS_PER_CONTACT)  # Hertz: at speed 6
    if engine == "lammps hooke":
        gamman = soft.gamman_for_restitution(e, stiffness, MEFF)
        variables = dict(kn=stiffness, gamman=gamman)
        t_c = soft.hooke_contact_time(gamman, stiffness, MEFF)
    else:
        gamman = None
        variables = dict(ymod=stiffness, restitution=e, ntypes=1)
        k = soft.hertz_stiffness("hertz_liggghts", stiffness, 0.25, soft.POISSON_LIGGGHTS)
        t_c = soft.contact_time_hertz(k, MEFF, hs_theory.mean_relative_speed(t0, MEFF))  # elastic, at the mean speed
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


# --- states, the ensemble, one engine's run -------------------------------------------------

def summarise(run, mass, t0, e, gamma0):
    times = np.array([f["t"] for f in run["frames"]])
    temps = np.array([temperature(f, mass) for f in run["frames"]])
    rel, worst, at = haff_deviation(times, temps, t0, e, gamma0)
    cpu_per_time = run["cpu_seconds"] / run["sim_time"]
    return dict(times=times.tolist(), T=temps.tolist(), T_haff=hs_theory.haff_temperature(times, t0, e, gamma0).tolist(),
                rel_deviation=rel.tolist(), max_abs_deviation=worst, max_at_time=at, cpu_seconds=run["cpu_seconds"],
                sim_time=run["sim_time"], cpu_seconds_per_unit_time=cpu_per_time, collisions=run["collisions"],
                settings=run["settings"])


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


def engine_tolerance(ens, engine, tolerances):
    """Allowed max |T/T_Haff - 1| for an engine: the ensemble's largest |mean| + sigmas s.d. over the
    measured times (plus soft_model for a soft engine: O(t_c Gamma0) and its restitution error)."""
    hard = max(abs(m) + tolerances["sigmas"] * s for m, s in zip(ens["mean"], ens["std"]))
    return hard + (tolerances["soft_model"] if engine in SOFT_ENGINES else 0.0)
