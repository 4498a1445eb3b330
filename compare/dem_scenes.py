#!/usr/bin/python3
"""DEM scenes side by side: LAMMPS's own granular example inputs run as they are (soft spheres,
Debian's stock lmp) and converted to hard spheres (reference_inputs/lammps/in.*_hardsphere, lmp_hs),
with the loop CPU time of each stage and the physics a DEM user compares.

Scenes:
  pour  examples/pour/in.pour: 3000 spheres poured by fix pour into a 20 x 20 floor (25000
        steps), then left to settle (25000 steps; the original's chute stage is left out). The
        hard run takes the soft contact's restitution (pairs 0.391, the floor 0.249), friction
        0.5 and the tangential spring's sticking limit (0.991, the floor 0.957), at several TC
        contact times (the soft contact's duration
        0.0375 is the converted input's default; 1e-4 is fix hardsphere's default).
Measured: atoms, translational and rotational kinetic energy at the end, the mean height, the
packing fraction of the bed between z = 1 and 4 (each sphere's volume inside that slab), the
largest overlap of the final state (hard runs: must be below 1e-9 of the diameter), the process's
CPU time and LAMMPS's loop time of each stage. A run that stops with an error is a row saying so.

  python3 -m compare.dem_scenes --out DIR [--build DIR] [--lmp-hs PATH] [--work DIR]

Writes DIR/dem_scenes.md and DIR/dem_scenes.json; exit status 1 if a check fails.
"""
import math
import resource
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from compare import harness
from compare import soft_spheres as soft
from compare.lammps_files import loop_times, read_data, thermo_blocks

ROOT = harness.ROOT
EXAMPLES = Path("/usr/share/lammps/examples")
OVERLAP_MAX = 1e-9
SLAB = (1.0, 4.0)


def soft_pour_input(out):
    """LAMMPS's in.pour with the chute stage replaced by a settling stage, the mean height in
    the thermo output and the final state written."""
    text = (EXAMPLES / "pour" / "in.pour").read_text()
    head = text[:text.index("unfix\t\tins")]
    head = head.replace("compute\t\t1 all erotate/sphere", "compute\t\t1 all erotate/sphere\ncompute\t\tzm all reduce ave z")
    head = head.replace("thermo_style\tcustom step atoms ke c_1 vol", "thermo_style\tcustom step atoms ke c_1 c_zm")
    return head + f"unfix\t\tins\nrun\t\t25000\nwrite_data\t{out}\n"


def slab_fraction(d, lo, hi, area):
    """Packing fraction between z = lo and hi: each sphere's volume inside the slab."""
    r = 0.5 * d.diameter
    z = d.pos[:, 2]

    def below(h):  # volume of each sphere below height h
        x = np.clip(h - (z - r), 0, 2 * r)
        return math.pi * x * x * (3 * r - x) / 3

    return float((below(hi) - below(lo)).sum() / (area * (hi - lo)))


def largest_overlap(d):
    """The largest overlap over the diameter (minimum image in x and y)."""
    lengths = d.lengths.copy()
    pos = d.pos - d.box[:, 0]
    pos[:, :2] = np.mod(pos[:, :2], lengths[:2])
    box = np.array([lengths[0], lengths[1], 1e9])
    pos[:, 2] -= pos[:, 2].min()
    tree = cKDTree(pos, boxsize=box)
    dmax = float(d.diameter.max())
    worst = 0.0
    for i, j in tree.query_pairs(dmax):
        dx = pos[i] - pos[j]
        dx[:2] -= lengths[:2] * np.round(dx[:2] / lengths[:2])
        contact = 0.5 * (d.diameter[i] + d.diameter[j])
        worst = max(worst, (contact - float(np.sqrt(dx @ dx))) / contact)
    return worst


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_lammps(lmp, infile, cwd, variables, log):
    """The run's output, its first ERROR line (or None), thermo blocks and process CPU seconds."""
    cmd = [lmp, "-in", infile, "-log", "none", "-echo", "none"]
    for k, v in variables.items():
        cmd += ["-var", k, v]
    before = children_cpu()
    p = harness.run_program(cmd, cwd=cwd, log=log, expect=None)
    cpu = children_cpu() - before
    text = p.stdout + p.stderr
    error = next((ln for ln in text.splitlines() if ln.startswith("ERROR")), None)
    # fix pour's warnings would split the thermo blocks
    blocks = thermo_blocks("\n".join(ln for ln in text.splitlines() if not ln.startswith("WARNING")))
    return text, error, blocks, cpu


def measure(name, run, data_file, area):
    text, error, blocks, cpu = run
    row = {"run": name, "stage seconds": [round(s, 2) for s, _, _ in loop_times(text)], "cpu": cpu, "error": error}
    rows = [r for b in blocks for r in b]
    if rows:
        last = rows[-1]
        row.update(step=int(last["Step"]), atoms=int(last["Atoms"]), ke=last["KinEng"], ke_rot=last["c_1"],
                   mean_z=last["c_zm"])
    if not error and Path(data_file).is_file():
        d = read_data(data_file)
        row["bed_fraction"] = slab_fraction(d, *SLAB, area)
        row["overlap"] = largest_overlap(d)
    return row


def pour(tools, work, log):
    m = math.pi / 6  # fix pour's spheres: diameter 1, density 1
    e_pair, t_contact = soft.hooke_restitution(50.0, 2000.0, m / 2), soft.hooke_contact_time(50.0, 2000.0, m / 2)
    e_wall = soft.hooke_restitution(50.0, 2000.0, m)
    scene = {"name": "pour", "e_pair": e_pair, "e_wall": e_wall, "t_contact": t_contact, "rows": []}
    d = work / "pour"
    d.mkdir(exist_ok=True)
    (d / "in.pour_soft").write_text(soft_pour_input("soft.data"))
    run = run_lammps(tools["lmp"], "in.pour_soft", d, {}, d / "soft.log")
    scene["rows"].append(measure("soft (gran/hooke/history, lmp 2021)", run, d / "soft.data", 400.0))
    log(f"pour soft: {scene['rows'][-1]['cpu']:.1f} CPU s")
    for tc in ("0.0375", "0.003", "1e-4"):
        out = f"hard_{tc}.data"
        run = run_lammps(tools["lmp_hs"], str(ROOT / "reference_inputs/lammps/in.pour_hardsphere"), d,
                         {"tc": tc, "out": out}, d / f"hard_{tc}.log")
        row = measure(f"hard, contact_time {tc}", run, d / out, 400.0)
        row["collisions"] = [r["f_1[1]"] for b in run[2] for r in b][-1] if run[2] else None
        scene["rows"].append(row)
        log(f"pour hard tc {tc}: {row['cpu']:.1f} CPU s, error {row['error']}")
    return scene


def check(scenes):
    failures = []
    for s in scenes:
        for r in s["rows"]:
            if r["run"].startswith("hard") and r.get("overlap", 0) > OVERLAP_MAX:
                failures.append(f"{s['name']} {r['run']}: overlap {r['overlap']:.2e} > {OVERLAP_MAX}")
            if r["run"].startswith("soft") and r["error"]:
                failures.append(f"{s['name']} {r['run']}: {r['error']}")
    return failures


def fmt(v, f="{:.4g}"):
    return "-" if v is None else f.format(v)


def short(error):
    """An error line without LAMMPS's source location, cut after its first clause."""
    if not error:
        return "-"
    text = error.split("(/")[0].replace("ERROR: ", "")
    return text.split(";")[0]


def reading(scene):
    """What the rows say, from their numbers: each hard run's CPU per stage against the soft
    run's, and how far its bed is from rest."""
    soft = scene["rows"][0]
    lines = []
    for r in scene["rows"][1:]:
        if r["error"]:
            lines.append(f"- {r['run']}: stopped at step {r.get('step', '?')} with {r.get('atoms', '?')} atoms in.")
            continue
        lines.append(f"- {r['run']}: CPU {r['cpu'] / soft['cpu']:.2f}x the soft run's; kinetic energy at the end "
                     f"{r['ke'] / soft['ke']:.3g}x the soft bed's, mean height {r['mean_z'] / soft['mean_z']:.4f}x, "
                     f"bed packing fraction {r['bed_fraction'] / soft['bed_fraction']:.4f}x.")
    return "\n".join(lines)


def markdown(scenes, generated):
    out = ["# DEM scenes: LAMMPS's granular examples, soft and hard", "", generated, "",
           "Each scene runs LAMMPS's own input (soft spheres, as shipped in Debian's `lammps-examples`) and its "
           "hard-sphere conversion in `reference_inputs/lammps/` ([recipe](../../dem_recipe.md)), one rank each. CPU: "
           "the whole process's user + system time; loop time: LAMMPS's wall-clock time of each run command (this "
           "machine is shared: compare CPU).", "",
           "The TC model makes a collision elastic when either sphere collided within `contact_time` before. In a "
           "bed, collisions follow each other far faster than the soft contact's duration, so with that time almost "
           "none dissipates: the bed stays agitated and, with no static friction holding its contacts, compacts "
           "beyond the soft bed. Shorter times dissipate more and cost more as the bed settles, and the default "
           "stops in an inelastic collapse. Beds at rest at a bounded cost need resting contacts between spheres "
           "(a contact network), which the hard model does not have yet.", ""]
    for s in scenes:
        out += [f"## {s['name']}", "",
                f"Matched laws: restitution {s['e_pair']:.3f} (pairs), {s['e_wall']:.3f} (floor), from the soft "
                f"contact (k_n 2000, gamma_n 50); its duration {s['t_contact']:.4f}. Bed: packing fraction between "
                f"z = {SLAB[0]:g} and {SLAB[1]:g}.", "",
                "| run | CPU (s) | loop time per stage (s) | atoms | KE | KE rot | mean z | bed phi | largest overlap / d | "
                "collisions | stopped by |",
                "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in s["rows"]:
            out.append(f"| {r['run']} | {r['cpu']:.1f} | {' + '.join(f'{x:.1f}' for x in r['stage seconds'])} | {r.get('atoms', '-')} | "
                       f"{fmt(r.get('ke'))} | {fmt(r.get('ke_rot'))} | {fmt(r.get('mean_z'), '{:.4f}')} | "
                       f"{fmt(r.get('bed_fraction'), '{:.4f}')} | {fmt(r.get('overlap'), '{:.1e}')} | "
                       f"{fmt(r.get('collisions'), '{:.0f}')} | {short(r['error'])} |")
        out += ["", reading(s), ""]
    return "\n".join(out)


def main(argv=None):
    ap = harness.parser(__doc__, programs=("lmp_hs",), work=True)
    a = ap.parse_args(argv)
    session = harness.Session("compare.dem_scenes", a, argv)
    tools = harness.tools(a, need=("lmp_hs", "lmp"))
    if not (EXAMPLES / "pour" / "in.pour").is_file():
        raise harness.InputError(f"{EXAMPLES}/pour/in.pour is missing: apt-get install lammps-examples")
    out = session.out()
    with session.workdir() as work:
        scenes = [pour(tools, work, session.log)]
    failures = check(scenes)
    data = {"scenes": scenes, "failures": failures, "seconds": session.seconds}
    report = session.write_report(out, "dem_scenes", markdown(scenes, session.generated()), data)
    return session.finish(failures, report)


if __name__ == "__main__":
    harness.main(main)
