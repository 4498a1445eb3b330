"""Runs in pieces: run N split, write_restart/read_restart (in a second LAMMPS: `clear` recreates
LAMMPS's style maps, dropping styles registered at start-up), commands and fixes between and
during runs, 'run ... pre no', rerun, and the unwrapped coordinates the fix leaves LAMMPS.
Groups: restart, between, unwrapped, pre_no, half_box, rerun."""
import numpy as np

from tests.lammps.lammps_runner import Cases, main, read_data, read_dump_frames
from compare.lammps_files import write_dump

cases = Cases(__file__)


def restart_file(ctx):
    """The 500-atom gas (init.data) after 50 + 50 steps as r.restart, and the two runs' output."""
    if not hasattr(ctx, "split_output"):
        ctx.state("init.data", "--n", 500, "--phi", 0.3)
        ctx.split_output = ctx.lammps("runs/split.lmp", vars=dict(data="init.data"))
    return ctx.split_output


@cases.case
def split_restart(ctx, case):
    """50 + 50 steps, write_restart, 50 more after read_restart: the collisions of one straight
    150-step run, thermo every step, energy kept across runs and the restart."""
    out1 = restart_file(ctx)
    ref = ctx.standalone("--read-data", "init.data", "--steps", 150, "--dt", 0.01)
    out2 = ctx.lammps("runs/restarted.lmp")
    blocks = out1.blocks + out2.blocks
    return {"thermo blocks": len(blocks), "rows of the first run": len(blocks[0]),
            "collisions": blocks[1][-1]["f_hs[1]"] + blocks[2][-1]["f_hs[1]"],
            "kinetic energy": blocks[2][-1]["KinEng"]}, dict(standalone=ref, start=blocks[0][0])


@cases.case
def velocity_displace(ctx, case):
    restart_file(ctx)
    rows = ctx.lammps("runs/velocity_displace.lmp").rows
    return {"collisions": rows[-1]["f_hs[1]"], "kinetic energy": rows[-1]["KinEng"],
            "temperature at the start": rows[0]["Temp"]}, dict(start=rows[0])


@cases.case
def berendsen(ctx, case):
    """The hard-sphere step takes up the thermostat's velocities: the gas heats, energy changes
    only by the rescaling."""
    restart_file(ctx)
    rows = ctx.lammps("runs/berendsen.lmp").rows
    return {"final temperature": rows[-1]["Temp"], "collisions": rows[-1]["f_hs[1]"]}, {}


@cases.case
def temp_rescale(ctx, case):
    """A fix acting only every 10 steps (temp/rescale at end_of_step): in serial the state is
    written for it on those steps and the rescaled velocities are taken up after; every thermo
    row after the first (steps 125 ... 300; the first rescale is at step 110) has T = 0.5."""
    restart_file(ctx)
    rows = ctx.lammps("runs/temp_rescale.lmp").rows
    temps = [r["Temp"] for r in rows[1:]]
    return {"rows after the first": len(temps), "lowest temperature": min(temps), "highest temperature": max(temps),
            "collisions": rows[-1]["f_hs[1]"]}, {}


@cases.case
def python_shift(ctx, case):
    """A fix that moves atoms at the end of a step (python/invoke, not known to leave positions
    alone): LAMMPS's x is compared after it, and moved atoms are taken up. Shifting every atom is a
    symmetry of the periodic gas: the centre of mass moves by 10 x 0.05 more than without the
    shift, and the collisions are those of the run without it."""
    restart_file(ctx)
    plain = ctx.lammps("runs/centre_of_mass.lmp").rows
    moved = ctx.lammps("runs/centre_of_mass_shifted.lmp").rows
    extra = (moved[-1]["c_cm[1]"] - moved[0]["c_cm[1]"]) - (plain[-1]["c_cm[1]"] - plain[0]["c_cm[1]"])
    return {"extra centre-of-mass shift": extra, "collisions": moved[-1]["f_hs[1]"],
            "collisions without the shift": plain[-1]["f_hs[1]"], "kinetic energy": moved[-1]["KinEng"],
            "steps re-run": moved[-1]["f_hs[6]"]}, dict(plain=plain[-1], start=moved[0])


@cases.case
def rounding_overlap(ctx, case):
    """Two approaching spheres 2 ulp inside contact (0.99999999999999956 apart), as a stepper's
    end state may leave them: accepted by both paths (the library's overlap_tolerance for double
    precision, as the standalone's --read-data), and they collide at once."""
    got = {}
    for path in ("auto", "ghosts"):
        rows = ctx.lammps("runs/rounding_overlap.lmp", vars=dict(path=path, x2="2.9999999999999996")).rows
        got[f"{path} path, gap at the start"] = rows[0]["v_gap"]
        got[f"{path} path, collisions"] = rows[-1]["f_hs[1]"]
        got[f"{path} path, velocity of atom 1 after"] = rows[-1]["v_v1"]
    return got, {}


@cases.case
def sorted_dump(ctx, case):
    """Unwrapped coordinates stay continuous: on one rank the fix writes LAMMPS's copy only on
    output steps (here every 20), with image flags from its own wrap counts, through LAMMPS's
    periodic wraps and atom sorts (every 7 steps). A wrong image shows as a jump of a box length;
    20 steps move an atom by ~0.3 at most."""
    restart_file(ctx)
    ctx.lammps("runs/sorted_dump.lmp")
    frames = read_dump_frames(ctx.path("traj.dump"))
    jump = np.abs(np.diff(np.array([f.positions() for f in frames]), axis=0)).max()
    box = read_data(ctx.path("init.data"))
    return {"frames": len(frames), "largest move in 20 steps": float(jump)}, dict(quarter_box=box.lengths.min() / 4)


@cases.case
def far_travel(ctx, case):
    """64 spheres in a box of ~4.4 diameters, 2000 steps with x written every step (dump every
    step) or only at the start and the end (dump every 2000, thermo at the end only): the
    unwrapped positions at the end agree."""
    ctx.state("small.data", "--n", 64, "--phi", 0.3)
    ends = []
    for every in (1, 2000):
        ctx.lammps("runs/far_travel.lmp", vars=dict(data="small.data", every=every, dump=f"far{every}.dump"))
        ends.append(read_dump_frames(ctx.path(f"far{every}.dump"))[-1].positions())
    start = read_data(ctx.path("small.data"))
    return {"difference at the end": float(np.abs(ends[0] - ends[1]).max()),
            "travel": float(np.abs(ends[0] - start.pos).max())}, dict(box=float(start.lengths.min()))


@cases.case
def pre_no(ctx, case):
    """'run N pre no every M COMMAND' skips the fix's setup between the pieces: commands that
    change velocities, delete or move atoms still take effect (the serial path re-reads the atoms;
    on several ranks LAMMPS's ghosts are taken up again, or one step runs for all atoms while
    LAMMPS re-neighbours), and no ghost copy disagrees with its owner after. The rows: the second
    piece, steps 50 .. 100."""
    restart_file(ctx)
    rows = ctx.lammps("runs/pre_no.lmp", vars=dict(command=f'"{case["command"]}"')).rows
    return {"kinetic energy": rows[-1]["KinEng"], "steps re-run": rows[-1]["f_hs[6]"],
            "collisions": rows[-1]["f_hs[1]"], "atoms": rows[0]["Atoms"], "temperature": rows[0]["Temp"],
            "time": rows[-1]["f_hs[4]"]}, dict(start=rows[0])


@cases.case
def half_box(ctx, case):
    """All atoms in the middle of one half of a long box: on 2 ranks the other sub-domain and its
    ghost shell start empty (that rank has no stepper but must join every step's collective calls)
    and fill up during the run. The collisions are the standalone stepper's."""
    ctx.lammps("runs/half_box.lmp", vars=dict(out="half.data"), np=1)
    ref = ctx.standalone("--read-data", "half.data", "--steps", 400, "--dt", 0.01)
    rows = ctx.lammps("runs/run_400.lmp", vars=dict(data="half.data")).rows
    return {"collisions": rows[-1]["f_hs[1]"], "kinetic energy": rows[-1]["KinEng"]}, \
        dict(standalone=ref, start=rows[0])


@cases.case
def rerun(ctx, case):
    """rerun reads snapshots and integrates nothing: a snapshot is not checked for overlaps (dumps
    round positions; atom 1 is moved onto atom 2 here), its pressure has no collision part, the
    collisions stay as they were, and pair_style hardsphere works there without the fix."""
    ctx.state("init.data", "--n", 500, "--phi", 0.3)
    ctx.lammps("runs/snapshot.lmp", vars=dict(data="init.data"))
    (snap,) = read_dump_frames(ctx.path("snap.dump"))
    one, two = (np.flatnonzero(snap["id"] == i)[0] for i in (1, 2))
    for axis, shift in zip("xyz", (0.5, 0.0, 0.0)):  # atom 1 overlaps atom 2
        snap[axis][one] = snap[axis][two] + shift
    write_dump(ctx.path("snap.dump"), [snap])
    out = ctx.lammps("runs/rerun.lmp", vars=dict(data="init.data"), expect_ok=False)
    blocks = out.blocks
    got = {"exit status": out.returncode, "thermo blocks": len(blocks), "rows per rerun": [len(b) for b in blocks[1:]]}
    refs = {}
    if out.returncode == 0 and len(blocks) == 3 and all(blocks[1:]):
        fixed, alone = blocks[1][0], blocks[2][0]
        got.update({"collisions in the rerun": fixed["f_hs[1]"], "rerun pressure": fixed["Press"],
                    "pressure without the fix": alone["Press"]})
        refs = dict(run=blocks[0][-1], fixed=fixed, alone=alone)
    else:
        print(out.text[-400:])
    return got, refs


if __name__ == "__main__":
    raise SystemExit(main(cases))
