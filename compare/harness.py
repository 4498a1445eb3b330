"""The one harness of every entry point of compare/ and bench/ (`python3 -m compare.NAME`,
`python3 -m bench.NAME`): where the programs are, where the output goes, the log and the exit status.

Options (each entry point takes those it needs, with these spellings only):
  --build DIR        the build directory (default: build/ in the repository root)
  --hardsphere PATH  the hardsphere program (default: BUILD/standalone/hardsphere)
  --lmp-hs PATH      lmp_hs, LAMMPS with the hardsphere styles (default: BUILD/plugin/lmp_hs)
  --mpirun PATH      the MPI launcher (default: mpirun on PATH)
  --out DIR          the report: DIR/NAME.md and DIR/NAME.json (figures DIR/NAME*.png); the committed
                     reports are docs/reports/<topic>/, so `--out docs/reports/<topic>` updates them
  --work DIR         intermediate files (states, runs, their logs), kept there; default: a temporary
                     directory, removed at the end
The other programs come from PATH: Debian's lmp, liggghts, mpirun, mpicc, valgrind.

Log: one line per finished piece of work, `[   12 s] text`, on standard output (Session.log).
Exit status: 0 every check passed; 1 a check failed (the report is written and lists it, and
`NAME: FAIL: ...` lines say which); 2 refused input: a bad option or value, a missing program
(InputError, and argparse's own usage errors); 3 a program failed while running (ProgramError) or
the script itself failed (a traceback). `main(run)` maps them, so every entry point ends alike.
"""
import argparse
import contextlib
import json
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

from compare import machine_info

ROOT = Path(__file__).resolve().parents[1]
REPORTS = ROOT / "docs" / "reports"
PROGRAMS = {"hardsphere": "standalone/hardsphere", "lmp_hs": "plugin/lmp_hs"}
ON_PATH = ("lmp", "liggghts", "mpirun", "mpicc", "valgrind")


class InputError(Exception):
    """Refused input: exit status 2."""


class ProgramError(RuntimeError):
    """A program the script ran failed: exit status 3."""


# --- options -------------------------------------------------------------------------------------

def parser(doc, programs=(), out=True, work=False, out_default=None):
    """An ArgumentParser with the harness's options: --build and, per name in programs
    ('hardsphere', 'lmp_hs', 'mpirun'), --hardsphere / --lmp-hs / --mpirun; --out (required unless
    out_default) and --work."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    if set(programs) & set(PROGRAMS):
        ap.add_argument("--build", default=str(ROOT / "build"), help="build directory (default: build)")
    if "hardsphere" in programs:
        ap.add_argument("--hardsphere", help="the hardsphere program (default: BUILD/standalone/hardsphere)")
    if "lmp_hs" in programs:
        ap.add_argument("--lmp-hs", help="lmp_hs (default: BUILD/plugin/lmp_hs)")
    if "mpirun" in programs:
        ap.add_argument("--mpirun", help="the MPI launcher (default: mpirun on PATH)")
    if out:
        ap.add_argument("--out", required=out_default is None, default=out_default,
                        help="report directory" + (f" (default: {out_default})" if out_default else ""))
    if work:
        ap.add_argument("--work", help="keep intermediate files here (default: a temporary directory)")
    return ap


def tools(args, need=()):
    """The programs: {'build', 'hardsphere', 'lmp_hs', 'lmp', 'liggghts', 'mpirun', 'mpicc', 'valgrind'},
    absolute paths or None when missing. InputError names the first of `need` that is missing."""
    build = Path(getattr(args, "build", None) or ROOT / "build").resolve()
    found = {"build": build}
    for name, rel in PROGRAMS.items():
        given = getattr(args, name, None)
        path = Path(given) if given else build / rel
        found[name] = str(path.resolve()) if path.is_file() else None
        if given and not found[name]:
            raise InputError(f"--{name.replace('_', '-')} {given}: no such program")
    for name in ON_PATH:
        given = getattr(args, name, None)
        found[name] = shutil.which(given or name)
        if given and not found[name]:
            raise InputError(f"--{name} {given}: no such program")
    for name in need:
        if not found[name]:
            where = f"{build / PROGRAMS[name]}" if name in PROGRAMS else "PATH"
            hint = "build it or give --build / --" + name.replace("_", "-") if name in PROGRAMS else \
                "scripts/setup.sh installs it"
            raise InputError(f"no {name} in {where} ({hint})")
    return found


# --- running programs ----------------------------------------------------------------------------

def run_program(cmd, cwd=None, log=None, expect=0, timeout=None, env=None, stdin=None):
    """Runs cmd (items made str); its output into the file `log` if given. Returns the
    CompletedProcess (text); ProgramError with the output's last lines if the exit status is not
    `expect` (None: any)."""
    cmd = [str(c) for c in cmd]
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env, input=stdin)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise ProgramError(f"{shlex.join(cmd[:4])} ...: {e}") from None
    if log:
        Path(log).write_text(p.stdout + p.stderr)
    if expect is not None and p.returncode != expect:
        tail = (p.stdout + p.stderr).strip().splitlines()[-5:]
        raise ProgramError(f"{shlex.join(cmd[:4])} ... ended with status {p.returncode}: " + " | ".join(tail))
    return p


def hardsphere_json(hardsphere, *args, cwd=None):
    """`hardsphere run ARGS --json -`: its summary."""
    return json.loads(run_program([hardsphere, "run", *args, "--json", "-"], cwd=cwd).stdout)


# --- one run of an entry point -------------------------------------------------------------------

def command_line(module, argv):
    """How the run was asked for, as a reader repeats it from the repository root: paths inside
    the repository relative to it, other absolute paths as DIR."""
    words = ["python3", "-m", module]
    for w in argv:
        p = Path(w)
        if p.is_absolute():
            r = p.resolve()
            w = str(r.relative_to(ROOT)) if r == ROOT or ROOT in r.parents else "DIR"
        words.append(w)
    return shlex.join(words)


class Session:
    """One run of an entry point: its command line, clock, log, work directory, reports and
    exit status."""

    def __init__(self, module, args=None, argv=()):
        self.module, self.args = module, args
        self.name = module.split(".")[-1]
        self.command = command_line(module, sys.argv[1:] if argv is None else argv)
        self.start = time.time()

    @property
    def seconds(self):
        return time.time() - self.start

    def log(self, text):
        print(f"[{self.seconds:7.0f} s] {text}", flush=True)

    @contextlib.contextmanager
    def workdir(self):
        """--work DIR (made, kept) or a temporary directory removed at the end."""
        given = getattr(self.args, "work", None)
        if given:
            path = Path(given).resolve()
            path.mkdir(parents=True, exist_ok=True)
            yield path
        else:
            with tempfile.TemporaryDirectory(prefix=f"{self.name}_") as d:
                yield Path(d)

    def out(self):
        """--out, made."""
        path = Path(self.args.out).resolve()
        path.mkdir(parents=True, exist_ok=True)
        return path

    def generated(self, versions=None, extra=""):
        """The report's 'Generated by' line: command, duration, machine and versions."""
        v = versions or {"machine": machine_info.machine(), "hardsphere": machine_info.commit()}
        parts = [f"hardsphere {v['hardsphere']}"]
        if v.get("lammps", "unknown") != "unknown":
            parts.append(f"LAMMPS {v['lammps']}")
        if v.get("liggghts", "unknown") != "unknown":
            parts.append(v["liggghts"])
        return f"Generated by `{self.command}`{extra} in {self.seconds:.0f} s on {v['machine']}; {', '.join(parts)}."

    def write_report(self, out, stem, markdown, data=None):
        """DIR/stem.md and (with data) DIR/stem.json; returns the markdown's path."""
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        if data is not None:
            (out / f"{stem}.json").write_text(json.dumps(data, indent=1, default=float) + "\n")
        (out / f"{stem}.md").write_text(markdown.rstrip("\n") + "\n")
        return out / f"{stem}.md"

    def finish(self, failures=(), report=None):
        """Prints the result; 1 if there are failures, else 0."""
        where = f"; report in {report}" if report else ""
        print(f"{self.name}: {len(failures)} failed checks{where}", flush=True)
        for f in failures:
            print(f"{self.name}: FAIL: {f}", flush=True)
        return 1 if failures else 0


class RowStore:
    """A report built up by several calls of one entry point (each measuring some rows, e.g. one N
    or one rank count): DIR/stem.json keeps every table's rows by key with the command and date
    that measured them, a call replaces only the rows it measured, and the markdown is rendered
    from the whole JSON (render(store) -> text), so `--from-json` re-renders without measuring."""

    def __init__(self, out, stem):
        self.path = Path(out) / f"{stem}.json"
        self.md = Path(out) / f"{stem}.md"
        self.data = json.loads(self.path.read_text()) if self.path.exists() else {"tables": {}}

    def put(self, table, key, row, session):
        row = dict(row, command=session.command, date=time.strftime("%Y-%m-%d"),
                   machine=machine_info.machine(), hardsphere=machine_info.commit())
        self.data["tables"].setdefault(table, {})[str(key)] = row
        self.save()

    def rows(self, table):
        return list(self.data["tables"].get(table, {}).values())

    def save(self):
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.path.write_text(json.dumps(self.data, indent=1, default=float) + "\n")

    def render(self, text):
        self.md.write_text(text.rstrip("\n") + "\n")
        return self.md


def measured_by(rows):
    """The commands, machines and commits that measured rows, as report lines."""
    seen = []
    for r in rows:
        line = f"`{r['command']}` ({r['date']}, {r['machine']}, hardsphere {r['hardsphere']})"
        if line not in seen:
            seen.append(line)
    return seen


def main(run, argv=None):
    """Runs run(argv) and exits with its status, mapping the harness's errors (module docstring)."""
    name = Path(sys.argv[0]).stem if sys.argv and sys.argv[0] else "script"
    try:
        status = run(sys.argv[1:] if argv is None else argv)
    except InputError as e:
        print(f"{name}: error: {e}", file=sys.stderr)
        status = 2
    except ProgramError as e:
        print(f"{name}: error: {e}", file=sys.stderr)
        status = 3
    except KeyboardInterrupt:
        raise
    except Exception:  # noqa: BLE001 - a script failure is status 3, not 1 (a failed check)
        traceback.print_exc()
        print(f"{name}: error: the script failed (above)", file=sys.stderr)
        status = 3
    sys.exit(status or 0)
