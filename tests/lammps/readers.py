"""Everything that reads LAMMPS's x, v and omega between output steps sees the current state.

On one rank the fix writes LAMMPS's copy of the atoms only on the steps something reads it
(docs/fix_hardsphere.md, Description). Each case runs 100 steps of the gas (1000 atoms at phi
0.3) with thermo at the first and last step only and one reader every 7 steps, none of whose
steps is an output step: a dynamic group (LAMMPS 2025 and 2026 update it from a list of its
own at post_force, 2021 at post_integrate), a compute invoked by fix
ave/time, a variable evaluated by fix print or fix halt, a dump, commands between the pieces of
'run N every M', and a Python function called by fix python/invoke. What each read (the atoms
that an atom-style selection on z and vz, or omega_z for rough spheres, holds) is compared with
the standalone stepper's state at the same steps (its dump every 7 steps); the serial path
equals it bit for bit, and on 2 ranks 100 steps stay within 1e-9 of it (identical.py), far from
moving an atom across the selection's bounds. A dynamic group's 'within' (LAMMPS 2026) reads a
neighbour list LAMMPS builds at re-neighbourings, which the owned + ghost path decides: that
list must hold every pair, as the standalone's positions say, at every read.
Groups: groups, computes, commands."""
import re

import numpy as np

from tests.lammps.lammps_runner import Cases, main, read_dump_frames

cases = Cases(__file__)

STEPS, EVERY = 100, 7
Z_RANGE = (3.0, 8.0)  # inside the box (0 to 12.04) away from its faces, where x is wrapped


WITHIN = 1.2  # group_within.lmp: atoms of ids above 500 within this distance of a selected one


def selection(rough, kind="spin"):
    """The per-atom quantity whose sign the selection takes (setup.lmp; c_w: omega_z) and the
    count of the atoms the selection holds in a dump frame: in Z_RANGE with that quantity
    positive (kind spin), in Z_RANGE (region), or atoms of ids up to 500 in Z_RANGE and the others
    within WITHIN of one of those (within: LAMMPS 2026's 'group ... dynamic half region mid within')."""
    lo, hi = Z_RANGE
    spin = "c_w" if rough else "vz"

    def count(frame):
        inside = (frame["z"] >= lo) & (frame["z"] <= hi)
        if kind == "spin":
            inside &= (frame["wz"] if rough else frame["vz"]) > 0
        if kind == "within":
            half = frame["id"] <= 500
            chosen = inside & half
            pos = np.stack([frame["x"], frame["y"], frame["z"]], axis=1)
            lengths = frame.box_hi - frame.box_lo
            d = pos[:, None, :] - pos[chosen][None, :, :]
            d -= lengths * np.round(d / lengths)
            inside = chosen | (~half & ((d ** 2).sum(axis=2) < WITHIN ** 2).any(axis=1))
        return int(inside.sum())
    return spin, count


def reference(ctx, rough):
    """The standalone's frames every 7 steps (and the last) of the same run, by step."""
    law = ["--tangential-restitution", 0.5] if rough else []
    data = "rough.data" if rough else "init.data"
    ctx.state(data, "--n", 1000, "--phi", 0.3, *law)
    dump = "sa_rough.dump" if rough else "sa.dump"
    ctx.standalone("--read-data", data, "--steps", STEPS, "--dt", 0.01, *law, "--dump", dump, "--dump-every", EVERY)
    return data, {f.timestep: f for f in read_dump_frames(ctx.path(dump))}


def run_reader(ctx, case, **extra):
    rough = case.get("rough", False)
    data, frames = reference(ctx, rough)
    sel, count = selection(rough, case.get("selection", "spin"))
    zlo, zhi = Z_RANGE
    law = dict(hs="tangential_restitution 0.5") if rough else {}
    if case.get("fix"):
        law = dict(hs=case["fix"])
    out = ctx.lammps(case["deck"], vars=dict(data=data, spin=sel, zlo=zlo, zhi=zhi, steps=STEPS, every=EVERY, **law,
                                             within=WITHIN, **extra))
    return out, frames, count


def compare_rows(rows, frames, count):
    """(steps read, steps whose count differs from the standalone's) of {step: count}."""
    wrong = [s for s, n in rows.items() if s not in frames or n != count(frames[s])]
    if wrong:
        s = wrong[0]
        print(f"info: first wrong read at step {s}: {rows[s]}, standalone "
              f"{count(frames[s]) if s in frames else 'no frame'}")
    return dict(reads=len(rows), **{"reads differing from the standalone": len(wrong)})


@cases.case
def dynamic_group(ctx, case):
    """A dynamic group's members after the run: those of its last update (step 98)."""
    out, frames, count = run_reader(ctx, case)
    members = int(re.search(r"^MEMBERS (\d+)", out.text, re.M).group(1))
    last = STEPS // EVERY * EVERY
    return dict(members=members), dict(standalone=count(frames[last]))


@cases.case
def printed_rows(ctx, case):
    """Rows 'READ step count' the reader printed (fix print, commands of 'run every')."""
    out, frames, count = run_reader(ctx, case)
    rows = {int(m.group(1)): int(float(m.group(2))) for m in re.finditer(r"^READ (\d+) (\S+)", out.text, re.M)}
    return compare_rows(rows, frames, count), {}


@cases.case
def ave_time(ctx, case):
    _, frames, count = run_reader(ctx, case)
    rows = {}
    for line in open(ctx.path("ave.txt")):
        if not line.startswith("#"):
            step, value = line.split()
            rows[int(step)] = int(float(value))
    return compare_rows(rows, frames, count), {}


@cases.case
def python_invoke(ctx, case):
    """Per-rank counts of fix python/invoke, summed over the ranks."""
    _, frames, count = run_reader(ctx, case)
    rows = {}
    for rank in range(ctx.np):
        for line in open(ctx.path(f"py_count.{rank}.txt")):
            step, n = map(int, line.split())
            rows[step] = rows.get(step, 0) + n
    return compare_rows(rows, frames, count), {}


@cases.case
def halt(ctx, case):
    """fix halt at the first sampled step past the middle of the run whose count no earlier
    sample had: a reader of stale rows halts at another step or not at all."""
    rough = case.get("rough", False)
    _, frames = reference(ctx, rough)
    _, count = selection(rough, case.get("selection", "spin"))
    seen, target, expected = set(), None, None
    for step in sorted(s for s in frames if s % EVERY == 0):
        n = count(frames[step])
        if step > STEPS // 2 and n not in seen:
            target, expected = n, step
            break
        seen.add(n)
    out, _, _ = run_reader(ctx, case, target=target)
    halted = int(re.search(r"^HALTED (\d+)", out.text, re.M).group(1))
    return dict(halted=halted), dict(expected=expected)


@cases.case
def dump(ctx, case):
    """Dump frames every 7 steps: the selection's count and the positions against the standalone."""
    _, frames, count = run_reader(ctx, case)
    lmp = read_dump_frames(ctx.path("frames.dump"))
    rows, dx = {}, 0.0
    for f in lmp:
        f.columns["wz"] = f["omegaz"]
        rows[f.timestep] = count(f)
        ref = frames.get(f.timestep)
        if ref is not None and np.array_equal(ref["id"], f["id"]):
            d = np.stack([f["x"] - ref["x"], f["y"] - ref["y"], f["z"] - ref["z"]], axis=1)
            lengths = f.box_hi - f.box_lo
            d -= lengths * np.round(d / lengths)
            dx = max(dx, float(np.abs(d).max()))
        else:
            dx = np.inf
    return dict(compare_rows(rows, frames, count), **{"max |dx|": dx}), {}


if __name__ == "__main__":
    raise SystemExit(main(cases))
