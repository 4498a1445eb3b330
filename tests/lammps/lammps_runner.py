"""The shared part of the LAMMPS checks: one module per feature beside this one (identical.py,
runs.py, ...), each with its input decks in decks/FEATURE/ and its expected values in FEATURE.yaml.

A feature module registers its cases with `cases = Cases(__file__)` and `@cases.case`, and ends
with `main(cases)`. Run from the repository root:

    python3 -m tests.lammps.FEATURE --lmp PATH --hs PATH [--plugin PATH] [--np 2 --mpirun PATH]
                                   [--group NAME] [--case NAME ...] [--list]

A case is a function of a Context (lmp, the standalone, a working directory) returning the
quantities it measured and the reference values they are compared with (e.g. the standalone's
JSON summary). FEATURE.yaml states, per case and quantity, what the value must be:

    equal: REF            exactly REF
    rel: EPS, ref: REF    |value / REF - 1| < EPS
    abs: EPS, ref: REF    |value - REF| < EPS
    below: X / above: X   value < X / value > X
    min: X / max: X       value >= X / value <= X
    is: true|false        a condition the case evaluated (a table complete, an order kept)
    contains: TEXT        a message holds TEXT

REF and X are numbers or names of reference values ('standalone.collisions'); `mpi:` holds the
check that replaces this one on more than one rank, `only: serial|mpi` limits a case or a
check to one of them, `since: DATE` runs a case only on LAMMPS releases from DATE (20250204) on.
A check whose quantity was not measured fails; a measured quantity without a check is printed
as information.
Each check prints one line naming the feature, case, rank count and quantity; the exit status
is 1 when any failed.

Decks are LAMMPS inputs; values come in as LAMMPS variables (-var data init.data), shared set-ups
through `include ${decks}/NAME.lmp`. Nothing in them is specific to lmp_hs: with --plugin PATH
every input starts with `plugin load PATH`, so the same checks run on a stock `lmp` that loads
hardsphereplugin.so.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np
import yaml

from compare.lammps_files import read_data, read_dump_frames, thermo_blocks, thermo_rows

HERE = Path(__file__).resolve().parent
DECKS = HERE / "decks"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")

__all__ = ["Cases", "Context", "main", "read_data", "read_dump_frames", "thermo_blocks", "thermo_rows"]


class LammpsFailed(Exception):
    pass


def mpi_command(mpirun, np_, cmd):
    """cmd on np_ MPI ranks (oversubscribed: the ranks may exceed the cores), or as it is for one."""
    return [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(np_)] + cmd if np_ > 1 else cmd


def plugin_line(plugin):
    """The first command of every input when the styles come from a plugin."""
    return f"plugin load {Path(plugin).resolve()}\n" if plugin else ""


class Output:
    """What one lmp run printed: returncode, text (stdout + stderr), its thermo blocks."""

    def __init__(self, returncode, text):
        self.returncode, self.text = returncode, text

    @property
    def blocks(self):
        return thermo_blocks(self.text)

    @property
    def rows(self):
        """The last thermo block."""
        return thermo_rows(self.text)

    @property
    def last(self):
        return self.rows[-1]

    @property
    def errors(self):
        return [ln for ln in self.text.splitlines() if "ERROR" in ln]

    def lines(self, phrase):
        return [ln for ln in self.text.splitlines() if phrase in ln]


class Context:
    """One feature's run: lmp (with the plugin), the standalone, the rank count, a working dir."""

    def __init__(self, args, work):
        self.lmp, self.plugin, self.hs, self.mpirun, self.np = args.lmp, args.plugin, args.hs, args.mpirun, args.np
        self.work = Path(work)
        self._standalone = {}

    @property
    def mpi(self):
        return self.np > 1

    def path(self, name):
        return str(self.work / name)

    def lammps(self, deck=None, *, vars=None, commands="", pre="", np=None, expect_ok=True, name="in.test"):
        """Runs decks/DECK (if given) preceded by `pre` and followed by `commands`, with -var NAME
        VALUE for each of vars, on np ranks (default: --np). Output, or LammpsFailed when the run
        fails and expect_ok."""
        np_ = self.np if np is None else np
        text = plugin_line(self.plugin) + pre + ((DECKS / deck).read_text() if deck else "") + commands
        (self.work / name).write_text(text)
        cmd = [self.lmp, "-in", name, "-log", "none", "-echo", "none", "-var", "decks", str(DECKS)]
        for k, v in (vars or {}).items():
            cmd += ["-var", k, str(v)]
        p = subprocess.run(mpi_command(self.mpirun, np_, cmd), cwd=self.work, env=ENV, capture_output=True,
                           text=True, timeout=300)
        out = Output(p.returncode, p.stdout + p.stderr)
        if expect_ok and p.returncode != 0:
            raise LammpsFailed(f"{deck or name} on {np_} rank(s) failed ({p.returncode}):\n{out.text[-3000:]}")
        return out

    def version(self):
        """The LAMMPS release as a date number (20210929), from the header of an empty input."""
        if not hasattr(self, "_version"):
            header = self.lammps(np=1, name="in.version").text
            m = re.search(r"LAMMPS \((\d+) (\w{3})\w* (\d{4})", header)
            months = "Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec".split()
            self._version = int(m.group(3)) * 10000 + (months.index(m.group(2)) + 1) * 100 + int(m.group(1))
        return self._version

    def standalone(self, *opts):
        """`hardsphere run OPTS --json -` in the working directory, run once per set of options."""
        key = tuple(map(str, opts))
        if key not in self._standalone:
            p = subprocess.run([self.hs, "run", *key, "--json", "-"], cwd=self.work, capture_output=True, text=True)
            if p.returncode != 0:
                raise LammpsFailed(f"hardsphere run {' '.join(key)} failed ({p.returncode}): {p.stderr[-2000:]}")
            self._standalone[key] = json.loads(p.stdout)
        return self._standalone[key]

    def state(self, name, *opts):
        """A data file `name` written by `hardsphere run OPTS --steps 0` (made once)."""
        self.standalone(*opts, "--steps", "0", "--write-data", name)
        return name

    def engine_masses(self, data):
        """An atomfile (for -var masses, decks/gas.lmp) of the masses the standalone computes for
        the atoms of data file `data`: density x 4/3 pi r^3 in its order of operations. LAMMPS 2026's
        read_data rounds 4/3 pi to another double than 2021, 2025 and the standalone, so masses of
        other diameters and densities may differ by an ulp (docs/fix_hardsphere.md); a comparison
        bit for bit starts both engines from the same masses."""
        d = read_data(self.work / data)
        radius = 0.5 * d.diameter
        mass = d.density * (4.0 * math.pi / 3.0 * radius * radius * radius)
        name = data.replace(".", "_") + "_masses"  # no dot: the deck compares it as a string in an if
        with open(self.work / name, "w") as f:
            f.write(f"# the standalone's masses of {data}\n{len(d)}\n")
            f.writelines(f"{i} {m!r}\n" for i, m in zip(d.ids.tolist(), mass.tolist()))
        return name

    def difference(self, ref, other, periodic=(True, True, True)):
        """Largest |dx| (minimum image on periodic axes) and |dv| between two data files' atoms."""
        a, b = read_data(self.work / ref), read_data(self.work / other)
        if not np.array_equal(a.ids, b.ids):
            return math.inf, math.inf
        dx = b.pos - a.pos
        per = np.array(periodic)
        dx[:, per] -= a.lengths[per] * np.round(dx[:, per] / a.lengths[per])
        return float(np.abs(dx).max()), float(np.abs(b.vel - a.vel).max())


# --- cases and their checks ------------------------------------------------------------------

class Cases:
    """The cases of one feature module and their checks from the YAML file beside it."""

    def __init__(self, module_file):
        self.feature = Path(module_file).stem
        self.spec = yaml.safe_load((Path(module_file).with_suffix(".yaml")).read_text())
        self.functions = {}
        grouped = {"group" in entry for entry in self.spec["cases"].values()}
        if len(grouped) > 1:  # a case without a group would run in no test of a split feature
            raise ValueError(f"{self.feature}.yaml: give every case a group, or none")

    def case(self, fn):
        self.functions[fn.__name__] = fn
        return fn

    def names(self):
        """Case names in the YAML file's order; each names a function or a `generic` runner."""
        return list(self.spec["cases"])

    def function(self, name):
        entry = self.spec["cases"][name]
        fn = self.functions.get(entry.get("function", name))
        if fn is None:
            raise KeyError(f"{self.feature}.yaml: case {name} has no function {entry.get('function', name)}")
        return fn


def _resolve(ref, refs):
    """A number, or the value at a dotted name in refs ('standalone.collisions')."""
    if not isinstance(ref, str):
        return ref
    value = refs
    for part in ref.split("."):
        if not isinstance(value, dict) or part not in value:
            raise KeyError(f"no reference value {ref!r}")
        value = value[part]
    return value


def _fmt(v):
    if isinstance(v, float):
        return f"{v:.17g}" if v == v and abs(v) < 1e300 else repr(v)
    return repr(v) if isinstance(v, str) else str(v)


def evaluate(check, value, refs):
    """(passed, text) of one check on one measured value."""
    if "equal" in check:
        ref = _resolve(check["equal"], refs)
        return value == ref, f"{_fmt(value)} == {check['equal']} ({_fmt(ref)})" if isinstance(check["equal"], str) \
            else f"{_fmt(value)} == {_fmt(ref)}"
    if "rel" in check:
        ref = _resolve(check["ref"], refs)
        dev = abs(value / ref - 1) if ref != 0 else math.inf
        return dev < check["rel"], f"{_fmt(value)} vs {check['ref']} {_fmt(ref)}: relative {dev:.2e} < {check['rel']:g}"
    if "abs" in check:
        ref = _resolve(check["ref"], refs)
        dev = abs(value - ref)
        return dev < check["abs"], f"{_fmt(value)} vs {check['ref']} {_fmt(ref)}: |difference| {dev:.2e} < {check['abs']:g}"
    if "min" in check or "max" in check:
        lo, hi = _resolve(check.get("min", -math.inf), refs), _resolve(check.get("max", math.inf), refs)
        return lo <= value <= hi, f"{_fmt(value)} in [{_fmt(lo)}, {_fmt(hi)}]"
    if "below" in check or "above" in check:
        ok, text = True, []
        if "above" in check:
            lo = _resolve(check["above"], refs)
            ok &= value > lo
            text.append(f"> {check['above']}" + (f" ({_fmt(lo)})" if isinstance(check["above"], str) else ""))
        if "below" in check:
            hi = _resolve(check["below"], refs)
            ok &= value < hi
            text.append(f"< {check['below']}" + (f" ({_fmt(hi)})" if isinstance(check["below"], str) else ""))
        return bool(ok), f"{_fmt(value)} " + " and ".join(text)
    if "is" in check:
        return bool(value) == check["is"], f"{check['is']}" + ("" if bool(value) == check["is"] else f" (got {value!r})")
    if "contains" in check:
        text, phrase = str(value), check["contains"]
        where = [ln for ln in text.splitlines() if phrase in ln]
        shown = where[0] if where else ([ln for ln in text.splitlines() if "ERROR" in ln] or [text[-600:]])[0]
        return bool(where), f"{phrase!r} {'in' if where else 'NOT in'} {shown.strip()!r}"
    raise ValueError(f"unknown check {check}")


def applies(entry, mpi):
    only = entry.get("only")
    return only is None or only == ("mpi" if mpi else "serial")


def run_case(cases, name, ctx):
    """Runs one case and its checks; the number of failed checks (a case that raised counts 1)."""
    entry = cases.spec["cases"][name]
    tag = f"{cases.feature}/{name} np={ctx.np}"
    if "since" in entry and ctx.version() < entry["since"]:  # a style newer than this LAMMPS
        print(f"skip: {tag}: needs LAMMPS {entry['since']} or later, this is {ctx.version()}")
        return 0
    try:
        measured, refs = cases.function(name)(ctx, entry)
    except Exception as e:  # a run that failed, a file missing: the case fails with the reason
        print(f"FAIL: {tag}: {type(e).__name__}: {e}")
        traceback.print_exc(file=sys.stdout)
        return 1
    checks = {q: (c.get("mpi", c) if ctx.mpi else c) for q, c in entry["quantities"].items() if applies(c, ctx.mpi)}
    failed = 0
    for q in sorted(set(measured) - set(entry["quantities"])):  # shown, checked elsewhere or not at all
        print(f"info: {tag}: {q} = {_fmt(measured[q])}")
    for q, check in checks.items():
        if q not in measured:
            print(f"FAIL: {tag}: {q}: not measured")
            failed += 1
            continue
        try:
            ok, text = evaluate(check, measured[q], refs)
        except (KeyError, TypeError, ValueError) as e:
            ok, text = False, f"{type(e).__name__}: {e}"
        print(("ok:   " if ok else "FAIL: ") + f"{tag}: {q}: {text}")
        failed += not ok
    return failed


def main(cases, argv=None):
    ap = argparse.ArgumentParser(description=sys.modules["__main__"].__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lmp", required=True, help="the LAMMPS program (lmp_hs, or a stock lmp with --plugin)")
    ap.add_argument("--plugin", default="", help="hardsphereplugin.so: every input starts with 'plugin load PATH'")
    ap.add_argument("--hs", required=True, help="the hardsphere program (standalone)")
    ap.add_argument("--mpirun", default="mpirun")
    ap.add_argument("--np", type=int, default=1, help="MPI ranks of every run (1: serial)")
    ap.add_argument("--group", help="only the cases of this group (FEATURE.yaml)")
    ap.add_argument("--case", nargs="+", help="only these cases")
    ap.add_argument("--list", action="store_true", help="list the groups and cases, run nothing")
    args = ap.parse_args(argv)
    args.lmp, args.hs = str(Path(args.lmp).resolve()), str(Path(args.hs).resolve())
    names = cases.names()
    if args.list:
        for n in names:
            print(f"{cases.spec['cases'][n].get('group', '-')}: {n}")
        return 0
    if args.group:
        names = [n for n in names if cases.spec["cases"][n].get("group") == args.group]
    if args.case:
        names = [n for n in names if n in args.case]
    if not names:
        sys.exit(f"{cases.feature}: no case selected")
    failed, ran = 0, 0
    with tempfile.TemporaryDirectory() as work:
        ctx = Context(args, work)
        for n in names:
            if not applies(cases.spec["cases"][n], ctx.mpi):
                continue
            ran += 1
            f = run_case(cases, n, ctx)
            failed += f
    print(f"{cases.feature}: {ran} cases on {args.np} rank(s), {failed} failed checks")
    return 1 if failed else 0
