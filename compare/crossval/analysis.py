"""From one engine run to one result row (and the curves for the figures); the agreement checks.

Z: hard engines from the collision virial (event engine: its block averages; stepper: chained
runs; lmp_hs: blocks of compute pressure), soft engines from the pair virial. A soft engine is
mapped to hard spheres by its Barker-Henderson diameters: phi_eff = pi/6 n sum x_i d_i^3 with
d_i = sigma_i - shift_ii, and Z_mapped = Z_soft * Z_BMCSL(phi) / Z_BMCSL(phi_eff), comparable
with the hard-sphere Z at the nominal phi.
"""
import math

import numpy as np

from compare import hard_sphere_theory as hs_theory
from compare import soft_spheres as soft
from compare.crossval import observables as obs
from compare.crossval import plan as xv_plan
from compare.crossval import states as xv_states
from compare.crossval.engines import mean_err

SOFT_MODEL = xv_plan.MODEL


def _reference(rows, state_label):
    for r in rows:
        if r["state"] == state_label and r["reference"]:
            return r
    return None


def _elastic(task, frame):
    return soft.elastic_energy(frame["pos"], frame["radius"], frame["lo"], frame["hi"], SOFT_MODEL[task.engine],
                               task.stiffness, xv_plan.poisson(task.engine))


def _speed_curve(frames, mass, bins):
    picks = frames[:: max(1, len(frames) // 4)]
    u = np.concatenate([obs.reduced_speeds(f, mass)[0] for f in picks])
    return np.histogram(u, bins, density=True)[0]


def analyse(task, run, rows):
    st = task.state
    species = st.species
    mass = xv_states.masses(st.path)
    frames = run["frames"]
    lo, hi = xv_states.box(st.path)  # the state's box, exact (LIGGGHTS dumps it to 6 digits)
    for f in frames:
        f["lo"], f["hi"] = lo, hi
    n = run["n"]
    row = dict(engine=task.engine, setting=task.label, state=st.label, n=n, phi=st.phi, composition=st.composition,
               kind=task.kind, precision=task.precision if task.engine == "stepper" else "double", dt=task.dt,
               ranks=run["ranks"], reference=task.reference, default=(task.engine == "stepper" and
                                                                      task.dt == xv_plan.DEFAULT_DT),
               stiffness=task.stiffness, bh_shift=task.shift, steps_per_contact=task.steps_per_contact,
               sim_time=run["sim_time"], steps=run["steps"])
    if "z" in run:
        row["Z"], row["Z_err"] = run["z"], run["z_err"]
    else:
        row["Z"], row["Z_err"] = mean_err(run["z_blocks"])
    ref = _reference(rows, st.label) if not task.reference else row
    row["Z_ref"] = ref["Z"] if ref else None
    row["Z_bmcsl"] = hs_theory.z_bmcsl(st.phi, species)
    row["Z_mapped"] = row["phi_eff"] = None
    if task.kind == "soft":
        eff = [(x, d - xv_plan.bh_shift(task.engine, task.stiffness, reff=d / 4), m) for x, d, m in species]
        row["phi_eff"] = st.phi * sum(x * d**3 for x, d, _ in eff) / sum(x * d**3 for x, d, _ in species)
        row["Z_mapped"] = row["Z"] * row["Z_bmcsl"] / hs_theory.z_bmcsl(row["phi_eff"], eff)
    within = xv_plan.TOLERANCES["within"]
    row["within_1pct"] = bool(ref and abs(row["Z"] / ref["Z"] - 1) <= within)
    row["within_1pct_mapped"] = bool(ref and row["Z_mapped"] is not None and abs(row["Z_mapped"] / ref["Z"] - 1)
                                     <= within)
    # timings
    row["cpu_seconds"] = run["cpu_seconds"]
    row["cpu_seconds_per_tau"] = run["cpu_seconds"] / run["sim_time"]
    row["cpu_seconds_per_particle_step"] = run["cpu_seconds"] / (n * run["steps"]) if run["steps"] else None
    row["wall_seconds"] = run.get("wall_seconds")
    # speeds
    row["ks_D"], row["ks_p"], row["T"] = obs.speed_ks(frames[-1], mass)
    # self-diffusion
    tau, msd, row["D"], row["D_err"] = obs.msd_diffusion(frames, st.msd_window)
    row["D_window"] = list(st.msd_window)
    row["D_enskog"] = hs_theory.enskog_diffusion(st.phi) if st.composition == "mono" else None
    # structure: contact values per pair of types (sigma_ij from the species' diameters)
    nframes = max(2, min(8, 64000 // n))  # ~64000 sphere-frames for every N
    g = obs.rdf(frames[:: max(1, len(frames) // nframes)])
    contacts = {}
    for key, (r, gr, counts) in g.items():
        if key == "all":
            continue
        a, b = key
        sij = (species[a - 1][1] + species[b - 1][1]) / 2
        value, err = obs.contact_value(r, gr, counts, sij)
        contacts[f"{a}-{b}"] = dict(g=value, err=err, bmcsl=hs_theory.contact_value(st.phi, species, a - 1, b - 1))
    row["g_contact"] = contacts
    # collision rate (soft: contacts started per unit time, from the every-step frames)
    if task.kind == "soft":
        started, elapsed = obs.contacts_started(dict(f, lo=lo, hi=hi) for f in run["contact_frames"])
        row["collision_rate"] = 2 * started / (n * elapsed)
        row["collision_rate_err"] = row["collision_rate"] / math.sqrt(max(started, 1))
    else:
        row["collision_rate"] = run["collision_rate"]
        row["collision_rate_err"] = run["collision_rate_err"]
    row["collision_rate_enskog"] = hs_theory.enskog_rate(st.phi, species)
    # energy: kinetic (+ elastic overlap energy for soft engines) over the frames
    if task.kind == "soft":
        e = np.array([obs.kinetic_energy(f, mass) + _elastic(task, f) for f in frames])
        row["energy_drift"] = float(np.abs(e - e[0]).max() / e[0])
        row["max_overlap"] = None
    elif "energy_drift" in run:
        row["energy_drift"], row["max_overlap"] = run["energy_drift"], run["max_overlap"]
    else:
        e = np.array([obs.kinetic_energy(f, mass) for f in frames])
        row["energy_drift"], row["max_overlap"] = float(np.abs(e - e[0]).max() / e[0]), None
    bins = np.linspace(0, 4.5, 46)
    curve = dict(msd=(tau, msd), rdf={str(k): (v[0], v[1]) for k, v in g.items()},
                 speeds=(bins, _speed_curve(frames, mass, bins)))
    return row, curve


def _pair_check(a, b, sigmas):
    diff = abs(a["Z"] - b["Z"])
    err = math.hypot(a["Z_err"], b["Z_err"])
    ok = diff <= sigmas * err
    return ok, f"{a['state']}: {a['setting']} Z {a['Z']:.4f}+-{a['Z_err']:.4f} vs {b['setting']} " \
               f"{b['Z']:.4f}+-{b['Z_err']:.4f} ({diff / err:.1f} sigma)"


def agreement_pairs(rows):
    """The hard-engine pairs whose Z must agree: runs of the same limit or the same setting."""
    pairs = []
    by_state = {}
    for r in rows:
        by_state.setdefault(r["state"], []).append(r)
    for state, rs in by_state.items():
        ref = next((r for r in rs if r["reference"]), None)
        steppers = [r for r in rs if r["engine"] == "stepper"]
        lmp = [r for r in rs if r["engine"] == "lmp_hs"]
        for precision in ("double", "float"):
            fine = [r for r in steppers if r["precision"] == precision]
            if ref and fine:
                pairs.append((ref, min(fine, key=lambda r: r["dt"])))  # finest step against the exact engine
        for r in lmp:
            same = [s for s in steppers if s["precision"] == "double" and s["dt"] == r["dt"]]
            if same:
                pairs.append((same[0], r))  # adapter against the standalone at the same dt
        if len(lmp) > 1:
            pairs.append((lmp[0], lmp[1]))  # serial against 2 ranks
    return pairs


def check_agreement(rows, plan):
    tol = plan.tolerances
    failures = []
    for a, b in agreement_pairs(rows):
        ok, text = _pair_check(a, b, tol["hard_z_sigmas"])
        if not ok:
            failures.append("hard Z: " + text)
    for state in {r["state"] for r in rows}:
        soft_rows = [r for r in rows if r["state"] == state and r["kind"] == "soft" and r["ranks"] == 1
                     and r["steps_per_contact"] == 20]
        for engine in {r["engine"] for r in soft_rows}:
            stiffest = min((r for r in soft_rows if r["engine"] == engine), key=lambda r: r["bh_shift"])
            ref = _reference(rows, state)
            dev = stiffest["Z_mapped"] / stiffest["Z_ref"] - 1
            noise = tol["hard_z_sigmas"] * math.hypot(stiffest["Z_err"], ref["Z_err"]) / ref["Z"]
            if abs(dev) > max(tol["soft_mapped_z"], noise):
                failures.append(f"soft Z: {state}: {stiffest['setting']} Z_mapped {stiffest['Z_mapped']:.4f} vs "
                                f"hard {stiffest['Z_ref']:.4f} ({100 * dev:+.2f}%)")
    for r in rows:
        if r["ks_p"] < tol["ks_p"]:
            failures.append(f"speeds: {r['state']}: {r['setting']} KS p = {r['ks_p']:.2g}")
    return failures
