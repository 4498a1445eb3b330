"""The stress suite's machinery: the case registry (@case), the context a case runs the program in
(Ctx: runs, JSON summaries, final states), the checks every run must pass (sound) and the helpers
the cases share. The cases are in tests/stress/cases.py, the table in tests/stress/report.py."""
import json
import math
import subprocess
from pathlib import Path

import numpy as np

from compare import lammps_files
from compare.lammps_files import read_data


class Case:
    def __init__(self, name, criterion, fn, quick=True):
        self.name, self.criterion, self.fn, self.quick = name, criterion, fn, quick


CASES = []


def case(name, criterion, quick=True):
    def wrap(fn):
        CASES.append(Case(name, criterion, fn, quick))
        return fn
    return wrap


# --- running the program ------------------------------------------------------------------

class Ctx:
    def __init__(self, hs, work, full):
        self.hs, self.work, self.full = hs, Path(work), full
        self.rows = []  # the JSON summary of every run that wrote one, for the table

    def run(self, *args, expect=0, timeout=1800):
        p = subprocess.run([self.hs, "run", *map(str, args)], capture_output=True, text=True, timeout=timeout,
                           cwd=self.work)
        if p.returncode != expect:
            raise Failure(f"exit {p.returncode} (expected {expect}): {p.stderr.strip()[:300]}")
        return p

    def json(self, *args, label=None):
        out = self.work / f"run{len(self.rows)}.json"
        data = self.work / f"run{len(self.rows)}.data"
        p = self.run(*args, "--json", out, "--write-data", data)
        j = json.loads(out.read_text())
        j["_stderr"] = p.stderr
        j["_final"] = read_data(data)
        j["_label"] = label or ("event" if "event" in map(str, args) else
                                "stepper " + j.get("precision", "") + " " + j.get("detect", ""))
        self.rows.append(j)
        return j


class Failure(Exception):
    pass


def check(cond, what):
    if not cond:
        raise Failure(what)


def write_data(path, atoms, box=((0, 10),) * 3):
    """atoms: rows (x, y, z, vx, vy, vz[, diameter[, density]]), ids from 1."""
    return lammps_files.write_data(path, lammps_files.spheres_from_rows(atoms, box=box, title="stress case"))


def nan_count(j):
    f = j["_final"]
    vals = np.concatenate([f.diameter, f.density, f.pos.ravel(), f.vel.ravel()]).tolist()
    for k in ("kinetic_energy_final", "temperature", "compressibility_factor", "max_overlap"):
        vals.append(j[k] if isinstance(j[k], (int, float)) else float("nan"))
    return sum(1 for x in vals if not math.isfinite(x))


def momentum_drift(j):
    """|p1 - p0| relative to sum m |v| (the scale momentum rounding is measured against)."""
    f = j["_final"]
    scale = float((f.mass * np.sqrt((f.vel ** 2).sum(axis=1))).sum())
    dp = math.sqrt(sum((a - b) ** 2 for a, b in zip(j["momentum_final"], j["momentum_initial"])))
    return dp / scale if scale > 0 else dp


def sound(j, energy=1e-12, overlap=0.0, momentum=1e-12):
    """The checks every run must pass: energy, momentum, overlap, NaN, no warning."""
    check(nan_count(j) == 0, f"{nan_count(j)} NaN values")
    check(abs(j["energy_rel_drift"]) <= energy, f"energy drift {j['energy_rel_drift']:.2e} > {energy:g}")
    walls = "w" in j["box"]["boundary"]
    if not walls:
        check(momentum_drift(j) <= momentum, f"momentum drift {momentum_drift(j):.2e} > {momentum:g}")
    check(j["max_overlap"] <= overlap, f"max overlap {j['max_overlap']:.2e} > {overlap:g}")
    # The only warning a sound run may carry is overlap detection's note on long steps.
    bad = [w for w in j.get("warnings", []) if not w.startswith("--detect overlap with steps")]
    check(not bad, f"warnings: {bad}")


def velocities(j):
    f = j["_final"]
    return {int(i): tuple(v) for i, v in zip(f.ids, f.vel.tolist())}


def positions(j):
    f = j["_final"]
    return {int(i): tuple(x) for i, x in zip(f.ids, f.pos.tolist())}


def close(a, b, tol):
    return all(abs(x - y) <= tol for i in a for x, y in zip(a[i], b[i]))


STEPPERS = [("double", "overlap"), ("double", "sweep"), ("float", "overlap"), ("float", "sweep")]


def every_engine(ctx, data, time_, dt, boundary="p", extra=(), event=True):
    """The state through each stepper variant and the event engine; returns {label: json}."""
    out = {}
    for prec, det in STEPPERS:
        out[f"{prec} {det}"] = ctx.json("--read-data", data, "--boundary", boundary, "--dt", dt, "--time", time_,
                                        "--precision", prec, "--detect", det, *extra)
    if event:
        out["event"] = ctx.json("--read-data", data, "--boundary", boundary, "--engine", "event", "--time", time_)
    return out


def sound_all(runs, float_energy=1e-6, float_overlap=None):
    for label, j in runs.items():
        if label.startswith("float"):
            sound(j, energy=float_energy, overlap=float_overlap if float_overlap is not None else j["overlap_tolerance"],
                  momentum=1e-5)
        else:
            sound(j, overlap=j["overlap_tolerance"])


# --- helpers the cases share ------------------------------------------------------------------

def analytic_free(atoms, t):
    return {i + 1: (a[0] + a[3] * t, a[1] + a[4] * t, a[2] + a[5] * t) for i, a in enumerate(atoms)}


def expect_state(runs, pos, vel, tol_double=1e-12, tol_float=1e-5):
    for label, j in runs.items():
        tol = tol_float if label.startswith("float") else tol_double
        check(close(positions(j), pos, tol), f"{label}: positions {positions(j)} != {pos}")
        check(close(velocities(j), vel, tol), f"{label}: velocities {velocities(j)} != {vel}")


def gas(ctx, name, *args):
    path = ctx.work / name
    ctx.run("--steps", 0, "--write-data", path, *args)
    return str(path)


def agree(a, b, what, rel):
    check(abs(a - b) <= rel * max(abs(a), abs(b)), f"{what}: {a} vs {b} (more than {rel:.0%} apart)")


def refused(ctx, needle, *args):
    p = ctx.run(*args, expect=2)
    check(p.stderr.startswith("hardsphere: error: ") and needle in p.stderr, f"message {p.stderr.strip()!r} lacks {needle!r}")
    leftovers = [f.name for f in ctx.work.iterdir() if ".tmp." in f.name]
    check(not leftovers, f"files left behind: {leftovers}")


def data_with(ctx, name, edit):
    """A valid data file of 4 spheres with one textual edit(text) -> text."""
    src = gas(ctx, "four.data", "--n", 4, "--box", 4, "--init", "random")
    path = ctx.work / name
    path.write_text(edit(Path(src).read_text()))
    return str(path)
