"""The stress suite's cases, in the order of the table (docs/reports/stress.md): each is a function
decorated with @case(name, pass criterion[, quick=False]) that raises Failure (check) when the
program gets it wrong. A new case goes here, in the class it belongs to."""
import math
import subprocess
import time

import numpy as np

from compare import lammps_files
from compare.lammps_files import read_data
from tests.stress.runner import (agree, analytic_free, case, check, close, data_with, every_engine, expect_state, gas,
                                 nan_count, refused, sound, sound_all, velocities, write_data)


# --- cases: contacts at exact touching, grazing, simultaneous ------------------------------

@case("touching pair, head-on", "touching and approaching at t = 0: velocities swap at once (analytic, 1e-12)")
def touching_head_on(ctx):
    for name, atoms, box in [
        ("inside", [(4, 5, 5, 1, 0, 0), (5, 5, 5, -1, 0, 0)], None),
        ("across a periodic face", [(0.25, 5, 5, -1, 0, 0), (9.25, 5, 5, 1, 0, 0)], None),
    ]:
        data = write_data(ctx.work / "pair.data", atoms)
        runs = every_engine(ctx, data, 0.5, 0.1)
        sound_all(runs)
        swapped = [a[:3] + tuple(-x for x in a[3:6]) for a in atoms]
        expect_state(runs, {k: ((p[0]) % 10, p[1], p[2]) for k, p in analytic_free(swapped, 0.5).items()},
                     {i + 1: a[3:6] for i, a in enumerate(swapped)})
        for label, j in runs.items():
            check(j["collisions"] == 1, f"{name}, {label}: {j['collisions']} collisions, expected 1")


@case("touching pair, receding or tangential", "no collision; straight lines (analytic, 1e-12)")
def touching_no_collision(ctx):
    for atoms in ([(4, 5, 5, -1, 0, 0), (5, 5, 5, 1, 0, 0)], [(4, 5, 5, 0, 1, 0), (5, 5, 5, 0, 0, 0)],
                  [(0.25, 5, 5, 1, 0, 0), (9.25, 5, 5, -1, 0, 0)]):
        data = write_data(ctx.work / "pair.data", atoms)
        runs = every_engine(ctx, data, 0.5, 0.1)
        sound_all(runs)
        expect_state(runs, {k: (p[0] % 10, p[1], p[2]) for k, p in analytic_free(atoms, 0.5).items()},
                     {i + 1: a[3:6] for i, a in enumerate(atoms)})
        for label, j in runs.items():
            check(j["collisions"] == 0, f"{label}: {j['collisions']} collisions, expected 0")


@case("grazing pair", "impact parameter exactly 1: straight lines to 1e-7 (a tangent contact is decided at sqrt(eps)); "
      "1 - 1e-9: one collision, sweep and event engine agree to 1e-9")
def grazing(ctx):
    atoms = [(2, 6, 5, 1, 0, 0), (5, 5, 5, 0, 0, 0)]
    data = write_data(ctx.work / "graze.data", atoms)
    runs = every_engine(ctx, data, 6, 0.25)
    sound_all(runs)
    expect_state(runs, analytic_free(atoms, 6), {1: (1, 0, 0), 2: (0, 0, 0)}, tol_double=1e-7, tol_float=1e-4)
    atoms = [(2, 6 - 1e-9, 5, 1, 0, 0), (5, 5, 5, 0, 0, 0)]
    data = write_data(ctx.work / "graze2.data", atoms)
    runs = every_engine(ctx, data, 6, 0.25)
    sound_all(runs)
    ref = runs["event"]
    check(ref["collisions"] == 1, f"event engine: {ref['collisions']} collisions, expected 1")
    j = runs["double sweep"]  # overlap detection does not see grazes, by design
    check(j["collisions"] == 1 and close(velocities(j), velocities(ref), 1e-9), "double sweep differs from event")


@case("Newton's cradle", "five touching spheres, one incoming: the last leaves with its velocity, the rest stop")
def cradle(ctx):
    atoms = [(3.5, 5, 5, 1, 0, 0)] + [(5 + k, 5, 5, 0, 0, 0) for k in range(5)]
    data = write_data(ctx.work / "cradle.data", atoms, box=((0, 20),) * 3)
    runs = every_engine(ctx, data, 2, 0.1)
    sound_all(runs)
    pos = {1: (4, 5, 5), 2: (5, 5, 5), 3: (6, 5, 5), 4: (7, 5, 5), 5: (8, 5, 5), 6: (10.5, 5, 5)}
    vel = {i: (0, 0, 0) for i in range(1, 6)}
    vel[6] = (1, 0, 0)
    expect_state(runs, pos, vel)


@case("simultaneous contacts", "3 spheres meeting at one point, a 13-sphere touching cluster hit: conserved, no overlap")
def simultaneous(ctx):
    c = 5.0
    rc = 1 / math.sqrt(3)  # three unit spheres at 120 degrees touch pairwise at this radius
    atoms = []
    for k in range(3):
        a = 2 * math.pi * k / 3
        atoms.append((c + (rc + 1) * math.cos(a), c + (rc + 1) * math.sin(a), c, -math.cos(a), -math.sin(a), 0))
    data = write_data(ctx.work / "triple.data", atoms)
    runs = every_engine(ctx, data, 3, 0.1)
    sound_all(runs)
    # FCC cluster: a centre touching its 12 neighbours, all at rest, hit by a sphere along x.
    s = 1 / math.sqrt(2)
    shell = [(x, y, 0) for x in (-s, s) for y in (-s, s)] + [(x, 0, z) for x in (-s, s) for z in (-s, s)] + \
            [(0, y, z) for y in (-s, s) for z in (-s, s)]
    atoms = [(c, c, c, 0, 0, 0)] + [(c + a, c + b, c + d, 0, 0, 0) for a, b, d in shell] + [(c - 2.5, c, c, 3, 0, 0)]
    data = write_data(ctx.work / "cluster.data", atoms, box=((0, 12),) * 3)
    runs = every_engine(ctx, data, 3, 0.05)
    sound_all(runs)
    for label, j in runs.items():
        check(j["collisions"] >= 3, f"{label}: {j['collisions']} collisions")


@case("spheres exactly at a wall", "touching a wall moving in, along, into a corner: mirrored exactly (analytic)")
def at_walls(ctx):
    atoms = [(0.5, 2, 2, -1, 0, 0), (0.5, 5, 5, 0, 1, 0), (0.5, 0.5, 0.5, -1, -1, -1), (9.5, 8, 8, 1, 0, 0),
             (5, 9.5, 2, 0, 0.5, 0)]
    data = write_data(ctx.work / "walls.data", atoms)
    runs = every_engine(ctx, data, 0.25, 0.05, boundary="w")
    sound_all(runs)
    pos = {1: (0.75, 2, 2), 2: (0.5, 5.25, 5), 3: (0.75, 0.75, 0.75), 4: (9.25, 8, 8), 5: (5, 9.375, 2)}
    vel = {1: (1, 0, 0), 2: (0, 1, 0), 3: (1, 1, 1), 4: (-1, 0, 0), 5: (0, -0.5, 0)}
    expect_state(runs, pos, vel)
    for label, j in runs.items():
        check(j["wall_collisions"] == 6, f"{label}: {j['wall_collisions']} wall bounces, expected 6")



# --- cases: extreme speeds, precision, long runs, dense states, size disparity ---------------

def with_fast_sphere(src, dst, factor):
    """Sphere 1 of a T = 1 state given `factor` times the rms speed along x."""
    data = read_data(src)
    data.vel[data.ids == 1] = (factor * math.sqrt(3.0), 0.0, 0.0)
    return lammps_files.write_data(dst, data)


@case("one sphere at 1e3 x the thermal speed", "stepper (auto, overlap, sweep) and event engine: conserved, no overlap "
      "(overlap detection: or a warning), collisions within 10% of each other")
def fast_1e3(ctx):
    fast_sphere(ctx, 1e3)


@case("one sphere at 1e6 x the thermal speed", "as above", quick=False)
def fast_1e6(ctx):
    fast_sphere(ctx, 1e6)


def fast_sphere(ctx, factor):
    # At 1e3, over 10 seeds the collisions against the event engine's had mean +0.2% and sd 1.1%
    # (auto, sweep), -3.0% and 1.5% (overlap, which misses grazes): |mean| + 4 sd <= 9.0%.
    base = gas(ctx, "gas.data", "--n", 300, "--phi", 0.2, "--seed", 3)
    data = with_fast_sphere(base, ctx.work / "fast.data", factor)
    t = 40 * 11.3 / (factor * math.sqrt(3))  # ~40 box crossings of the fast sphere
    ref = ctx.json("--read-data", data, "--engine", "event", "--time", t)
    sound(ref, overlap=ref["overlap_tolerance"])
    for det in ("auto", "overlap", "sweep"):
        j = ctx.json("--read-data", data, "--dt", t / 20, "--time", t, "--detect", det)
        if det == "overlap" and j["max_overlap"] > j["overlap_tolerance"]:
            # Overlap detection misses grazes of the fast sphere; the run must say so.
            check(any("overlap by up to" in w for w in j["warnings"]), "overlap left without a warning")
            check("hardsphere: warning: spheres overlap" in j["_stderr"], "no warning on stderr")
            j = dict(j, max_overlap=0.0, warnings=[])
        sound(j, overlap=j["overlap_tolerance"])
        check(j["substeps"] > j["steps"], f"{det}: steps were not split ({j['substeps']} sub-steps)")
        agree(j["collisions"], ref["collisions"], f"collisions, {det} against event", 0.1)


@case("float against double", "same gas 1e8 particle-steps (quick: 1e6): Z and collision rate within 1%, "
      "float energy drift < 1e-4")
def float_double(ctx):
    # Quick, over 10 seeds: float / double - 1 had mean -0.14% and sd 0.22% for Z, 0.03% and 0.50%
    # for the rate (|mean| + 4 sd: 1.0% and 2.0%), so quick allows 1.5% and 2.5%; the full run's 100x
    # the particle-steps cut the sd ~10x. The float drift had sd 1e-8.
    n, steps = (10000, 10000) if ctx.full else (2000, 500)
    data = gas(ctx, "fd.data", "--n", n, "--phi", 0.3, "--seed", 8)
    runs = {p: ctx.json("--read-data", data, "--steps", steps, "--precision", p) for p in ("double", "float")}
    sound(runs["double"])
    sound(runs["float"], energy=1e-4, overlap=runs["float"]["overlap_tolerance"], momentum=1e-5)
    agree(runs["float"]["compressibility_factor"], runs["double"]["compressibility_factor"], "Z",
          0.01 if ctx.full else 0.015)
    agree(runs["float"]["collision_rate_per_particle"], runs["double"]["collision_rate_per_particle"], "rate",
          0.01 if ctx.full else 0.025)


@case("clock far from zero", "1e8 steps (quick: 1e6) of 27 spheres, and the event engine over the same time: "
      "conserved, rates within 3%")
def long_clock(ctx):
    # Quick, over 10 seeds: the rate ratio - 1 had mean -0.10% and sd 0.28% (|mean| + 4 sd = 1.2%).
    steps = 100_000_000 if ctx.full else 1_000_000
    data = gas(ctx, "lc.data", "--n", 27, "--box", 6, "--seed", 4)
    j = ctx.json("--read-data", data, "--steps", steps, "--dt", 0.01)
    sound(j, energy=1e-9, momentum=1e-9)
    check(j["sim_time"] == steps * 0.01 or abs(j["sim_time"] / (steps * 0.01) - 1) < 1e-9, "simulated time")
    ref = ctx.json("--read-data", data, "--engine", "event", "--time", steps * 0.01)
    sound(ref, energy=1e-9, overlap=ref["overlap_tolerance"], momentum=1e-9)
    agree(j["collision_rate_per_particle"], ref["collision_rate_per_particle"], "collision rate", 0.03)


@case("dense states", "phi 0.55-0.62 (N = 500) for 1e5 collisions per sphere (quick: 1e3): both engines conserve "
      "energy (1e-10 after 2.5e7 collisions), no overlap; over the first 1e3 collisions per sphere their rates agree within 6.5% (over 10 "
      "seeds the stepper's rate against the event engine's spread by 1.4% at phi 0.55 and 1.5% at 0.60, means -0.1% and -0.2%; later the "
      "metastable states age or crystallize at different times)")
def dense(ctx):
    per_sphere = 1e5 if ctx.full else 1e3
    for phi in ((0.55, 0.58, 0.60, 0.62) if ctx.full else (0.55, 0.60)):
        data = gas(ctx, f"dense{phi}.data", "--n", 500, "--phi", phi, "--seed", 6)
        probe = ctx.json("--read-data", data, "--engine", "event", "--time", 1)
        t_short = 1e3 / probe["collision_rate_per_particle"]
        ref = ctx.json("--read-data", data, "--engine", "event", "--time", t_short)
        j = ctx.json("--read-data", data, "--time", t_short, "--dt", 0.002)
        agree(j["collision_rate_per_particle"], ref["collision_rate_per_particle"], f"rate at phi {phi}", 0.065)
        t = per_sphere / probe["collision_rate_per_particle"]
        for run in (ctx.json("--read-data", data, "--engine", "event", "--time", t),
                    ctx.json("--read-data", data, "--time", t, "--dt", 0.002)):
            sound(run, energy=1e-10, overlap=run["overlap_tolerance"])
            check(run["collisions"] >= 0.4 * per_sphere * 500 / 2, f"only {run['collisions']} collisions at phi {phi}")


@case("size and mass disparity", "one sphere of diameter 10 or 20 and mass 1e4 among unit spheres between walls: "
      "conserved, no overlap, collisions within 5% of the event engine")
def disparity(ctx):
    # Quick (400 spheres, 4 time units), over 10 seeds: the stepper's collisions and wall bounces
    # equalled the event engine's every time (the runs had not decorrelated).
    import random
    rng = random.Random(5)
    for big in (10, 20):
        box = 30.0
        atoms = [(15, 15, 15, 0, 0, 0, float(big), 1e4 / (math.pi / 6 * big ** 3))]
        while len(atoms) < (1200 if ctx.full else 400):
            p = [rng.uniform(0.5, box - 0.5) for _ in range(3)]
            if math.dist(p, (15, 15, 15)) < big / 2 + 0.5 or any(math.dist(p, a[:3]) < 1 for a in atoms[1:]):
                continue
            atoms.append((*p, rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
        data = write_data(ctx.work / f"big{big}.data", atoms, box=((0, box),) * 3)
        t = 20 if ctx.full else 4
        ref = ctx.json("--read-data", data, "--boundary", "w", "--engine", "event", "--time", t)
        sound(ref, overlap=ref["overlap_tolerance"])
        j = ctx.json("--read-data", data, "--boundary", "w", "--time", t, "--dt", 0.01)
        sound(j, overlap=j["overlap_tolerance"])
        agree(j["collisions"], ref["collisions"], f"collisions, diameter {big}", 0.05)
        agree(j["wall_collisions"], ref["wall_collisions"], f"wall bounces, diameter {big}", 0.05)



# --- cases: the robustness issue's defect classes -------------------------------------------

@case("class 2: arithmetic overflow", "box -1e308..1e308, x = 1e17, dt 1e300, mass 1e-300, speed 1e200, T 1e308: "
      "refused (exit 2, value named)")
def overflow(ctx):
    wide = write_data(ctx.work / "wide.data", [(5, 5, 5, 0, 0, 0)], box=((-1e308, 1e308), (0, 10), (0, 10)))
    refused(ctx, "1e+308", "--read-data", wide, "--steps", 1)
    far = write_data(ctx.work / "far.data", [(1e17, 5, 5, 0, 0, 0), (5, 5, 5, 0, 0, 0)])
    refused(ctx, "x = 1e+17", "--read-data", far, "--steps", 1)
    fast = write_data(ctx.work / "fast.data", [(5, 5, 5, 1e200, 0, 0), (2, 2, 2, 0, 0, 0)])
    refused(ctx, "speed 1e+200", "--read-data", fast, "--steps", 1)
    for opt, needle in (("--dt=1e300", "dt = 1e+300"), ("--mass=1e-300", "mass 1e-300"), ("--temperature=1e308", "temperature")):
        refused(ctx, needle, "--n", 100, "--phi", 0.2, "--steps", 10, opt, "--json", "out.json")


@case("class 3: long steps", "200 spheres in a box of 8.06: dt 2 and 5 keep the event engine's collision rate (3%)")
def long_steps(ctx):
    # Over 10 seeds the rate ratio - 1 had mean 0.06% and sd 0.40% (dt 2), 0.02% and 0.36% (dt 5).
    data = gas(ctx, "ls.data", "--n", 200, "--box", 8.06, "--seed", 11)
    ref = ctx.json("--read-data", data, "--engine", "event", "--time", 200)
    for dt in (2, 5):
        j = ctx.json("--read-data", data, "--dt", dt, "--time", 200)
        sound(j)
        agree(j["collision_rate_per_particle"], ref["collision_rate_per_particle"], f"rate at dt {dt}", 0.03)


@case("class 4: float far from the origin", "the box moved to 1e6: float run within 5% of the run at the origin, "
      "no overlap")
def far_float(ctx):
    # Over 10 seeds far / near collisions - 1 had mean 0.08% and sd 0.80% (|mean| + 4 sd = 3.3%).
    base = gas(ctx, "base.data", "--n", 200, "--box", 8.06, "--seed", 12)
    moved = read_data(base)
    moved.pos += 1e6
    moved.box = np.array([(1e6, 1e6 + moved.box[0][1])] * 3)
    moved = lammps_files.write_data(ctx.work / "moved.data", moved)
    near = ctx.json("--read-data", base, "--steps", 2000, "--precision", "float")
    j = ctx.json("--read-data", moved, "--steps", 2000, "--precision", "float")
    sound(j, energy=1e-4, overlap=j["overlap_tolerance"], momentum=1e-5)
    agree(j["collisions"], near["collisions"], "collisions far against near", 0.05)


@case("class 5: runs that would not end", "--time 1e300 and a sphere at 1e90 in the event engine, 1e14 steps: "
      "refused up front")
def endless(ctx):
    refused(ctx, "events", "--n", 100, "--engine", "event", "--time", 1e300)
    fast = write_data(ctx.work / "fast.data", [(5, 5, 5, 1e90, 0, 0), (2, 2, 2, 0, 0, 0)])
    refused(ctx, "events", "--read-data", fast, "--engine", "event", "--time", 1)
    refused(ctx, "particle-steps", "--n", 100, "--steps", 100_000_000_000_000)


@case("class 9: overlap at the end", "a graze missed by overlap detection leaves an overlap of 0.1: warned on "
      "stderr and in the JSON")
def overlap_warning(ctx):
    data = write_data(ctx.work / "g.data", [(5, 5, 5, 2, 0, 0), (6, 5.9, 5, 0, 0, 0), (7, 5, 5, 0, 0, 0)],
                      box=((0, 20),) * 3)
    j = ctx.json("--read-data", data, "--dt", 1, "--steps", 1, "--detect", "overlap")
    check(abs(j["max_overlap"] - 0.1) < 1e-9, f"overlap {j['max_overlap']}")
    check(any("overlap by up to" in w for w in j["warnings"]), "no JSON warning")
    check("hardsphere: warning: spheres overlap by up to" in j["_stderr"], "no warning on stderr")



@case("class 10: resting contacts", "a sphere, a stack of two and a sphere at 1e-16 into the floor, at rest under "
      "gravity 1, both engines for time 10: within 1e-4 of their contacts, floor force = weight to 0.1%")
def resting(ctx):
    atoms = [(2, 2, 0.5, 0, 0, 0), (6, 6, 0.5, 0, 0, 0), (6, 6, 1.5, 0, 0, 0), (2, 7, 0.5, 0, 0, -1e-16)]
    data = write_data(ctx.work / "resting.data", atoms)
    for engine in ("stepper", "event"):
        step = ("--dt", 0.01) if engine == "stepper" else ()
        j = ctx.json("--read-data", data, "--boundary", "p,p,w", "--gravity", "0,0,-1", "--engine", engine,
                     "--time", 10, *step, label=f"{engine} resting")
        f = j["_final"]
        heights = f.pos[:, 2] - np.array([0.5, 0.5, 1.5, 0.5])
        check(heights.min() >= -1e-12 and heights.max() <= 1e-4, f"{engine}: heights above contact {heights}")
        weight_pressure = float(f.mass.sum()) / (2 * 10 * 10)  # floor force m g over both walls' area
        check(abs(j["wall_pressure"][2] / weight_pressure - 1) < 1e-3,
              f"{engine}: wall pressure {j['wall_pressure'][2]} against the weight's {weight_pressure}")
        check(j["resting_contacts"] > 0 and j["wall_collisions"] == 0,
              f"{engine}: {j['resting_contacts']} resting contacts, {j['wall_collisions']} bounces")


@case("class 11: jammed contact chains", "two spheres pressed between walls two diameters apart, a simple cubic "
      "lattice at contact: refused by both engines (exit 2, atoms named) within seconds")
def jammed(ctx):
    pressed = write_data(ctx.work / "pressed.data", [(2, 2, 0.5, 0.1, 0, 1), (2, 2, 1.5, 0, 0.2, -1)],
                         box=((0, 4), (0, 4), (0, 2)))
    rng = np.random.default_rng(3)
    lattice = [(x + 0.5, y + 0.5, z + 0.5, *rng.normal(size=3)) for x in range(4) for y in range(4) for z in range(4)]
    cubic = write_data(ctx.work / "cubic.data", lattice, box=((0, 4),) * 3)
    for engine in ("stepper", "event"):
        refused(ctx, "jammed spheres: atoms", "--read-data", pressed, "--boundary", "p,p,w", "--engine", engine,
                "--time", 0.05)
        refused(ctx, "jammed spheres: atoms", "--read-data", cubic, "--engine", engine, "--time", 0.05)


@case("class 12: tiny restitution", "--restitution 1e-13 and 5e-324 at phi 0.3: both engines run, cool and keep "
      "pairs apart")
def tiny_restitution(ctx):
    for e in ("1e-13", "5e-324"):
        for engine in ("stepper", "event"):
            j = ctx.json("--n", 500, "--phi", 0.3, "--restitution", e, "--engine", engine, "--time", 5,
                         label=f"{engine} e = {e}")
            check(j["max_overlap"] <= 1e-9 and nan_count(j) == 0, f"{engine}, e {e}: overlap {j['max_overlap']}")
            check(j["kinetic_energy_final"] < 0.1 * j["kinetic_energy_initial"],
                  f"{engine}, e {e}: kinetic energy {j['kinetic_energy_final']} of {j['kinetic_energy_initial']}")


@case("class 1: initial states finish", "n = 9, 10, 12, 50, 60 and 4500 at phi 0.3 and 0.45, and phi 0.62: made "
      "within a minute each")
def init_finishes(ctx):
    for n in (9, 10, 12, 50, 60, 4500):
        for phi in (0.3, 0.45):
            ctx.run("--n", n, "--phi", phi, "--steps", 0, timeout=60)
    ctx.run("--n", 4000, "--phi", 0.62, "--steps", 0, timeout=60)


@case("class 6: data-file gaps", "duplicate Velocities id, non-integer image flags, a second 'atom types', a short "
      "Masses section: refused with file:line")
def reader_gaps(ctx):
    def dup_velocity(t):
        head, vel = t.split("Velocities")
        rows = vel.strip().splitlines()
        return head + "Velocities\n\n" + "\n".join([rows[0], rows[0]] + rows[2:]) + "\n"

    def image_flags(t):
        head, rest = t.split("Atoms # sphere")
        rows = rest.strip().split("\n\n")[0].splitlines()
        bad = rows[0].rsplit(" ", 3)[0] + " a b c"
        return t.replace(rows[0], bad, 1)

    cases = [
        ("dup_vel.data", dup_velocity, "given twice"),
        ("images.data", image_flags, "'a'"),
        ("types.data", lambda t: t.replace("1 atom types", "1 atom types\n2 atom types"), "atom types"),
        ("masses.data", lambda t: t.replace("\nAtoms # sphere", "\nMasses\n\n1\n\nAtoms # sphere"), "mass line"),
    ]
    for name, edit, needle in cases:
        p = ctx.run("--read-data", data_with(ctx, name, edit), "--steps", 1, expect=2)
        check(f"{name}:" in p.stderr and needle in p.stderr, f"{name}: {p.stderr.strip()!r}")


@case("class 7: files left behind", "two outputs on one path refused before anything is written; SIGTERM and SIGINT "
      "mid-run leave no temporary file")
def files_left(ctx):
    import signal
    refused(ctx, "", "--n", 50, "--steps", 10, "--json", "x", "--write-data", "./x")
    check(not (ctx.work / "x").exists(), "x was created")
    for sig in (signal.SIGTERM, signal.SIGINT):
        out = ctx.work / f"sig{int(sig)}"
        out.mkdir()
        args = ["--n", 20000, "--phi", 0.3, "--steps", 100000, "--dump", "t.dump", "--dump-every", 10, "--json", "s.json",
                "--write-data", "f.data"]
        # As from a terminal: a shell's background job (this suite under `cmd &`) starts with SIGINT
        # ignored, and the program rightly keeps an ignored signal ignored.
        p = subprocess.Popen([ctx.hs, "run", *map(str, args)], cwd=out, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, preexec_fn=lambda s=sig: signal.signal(s, signal.SIG_DFL))
        deadline = time.time() + 60
        while time.time() < deadline and not any(".tmp." in f.name for f in out.iterdir()):
            time.sleep(0.05)
        time.sleep(0.3)
        p.send_signal(sig)
        rc = p.wait(timeout=60)
        check(rc == -sig, f"exit {rc} after signal {int(sig)}")
        check(list(out.iterdir()) == [], f"left behind: {[f.name for f in out.iterdir()]}")


@case("class 8: exit status", "unknown option, bad number, --n 1e12, a header of 99999999999999 atoms: exit 2 with "
      "'hardsphere: error:'")
def exit_status(ctx):
    refused(ctx, "--frobnicate", "--frobnicate", 3)
    refused(ctx, "abc", "--n", "abc")
    refused(ctx, "1000000000000", "--n", 1000000000000)
    huge = data_with(ctx, "huge.data", lambda t: t.replace("4 atoms", "99999999999999 atoms"))
    refused(ctx, "99999999999999", "--read-data", huge, "--steps", 1)
