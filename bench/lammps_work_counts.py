#!/usr/bin/python3
"""Work counts of `fix hardsphere` under MPI that do not depend on the machine: instructions per
rank counted by callgrind, taken as the difference of two run lengths so that set-up cancels,
beside each rank's MPI messages, bytes and collective calls per step (an MPI profiling
interposer, bench/mpi_traffic/, built with mpicc). The report has a table per engine and scaling:
strong scaling (--n) relative to the 1-rank run's sum, or weak scaling (--weak N per rank)
relative to its per-rank count; the busiest rank over the mean; LAMMPS `gran/hooke` on the same
states is the peer's figure.

Counts, never timings, so oversubscribed ranks are fine: only each rank's main thread is counted
and the MPI library's objects are left out (its progress threads and its polling while a rank
waits depend on timing; with them a rank's count varies by 10% and more from run to run).

  python3 -m bench.lammps_work_counts --build PORTABLE --out DIR [--n 256000 | --weak 32000] [--phi 0.3]
      [--ranks 2 4 8] [--grid] [--steps 10 50] [--no-peer] [--mpirun PATH] [--cache FILE]
  python3 -m bench.lammps_work_counts --out DIR --from-json

valgrind 3.19 has no AVX-512: give a build made with -DHS_NATIVE=OFF (--build, or --lmp-hs and
--hardsphere). --grid decomposes 8 ranks as 2 x 2 x 2 (else LAMMPS's default grid, slabs for 2
ranks). DIR/lammps_work_counts.json keeps the per-rank counts of every call (a row per engine,
spheres, ranks, grid and run lengths; a call replaces the rows it measured), so strong and weak
scaling from several calls make one report, DIR/lammps_work_counts.md; --from-json only renders
the markdown again. --cache keeps each finished row in FILE while a long call runs.
"""
import glob
import json
import os
import re
import tempfile
from pathlib import Path

from compare import harness

HARD = """units lj
atom_style sphere
boundary p p p
{processors}
read_data {data}
pair_style hardsphere
pair_coeff * *
neighbor 0.5 bin
neigh_modify every 1 delay 0 check yes
timestep 0.01
fix hs all hardsphere
thermo {steps}
run {steps}
"""

# The soft peer: Hookean contacts stiff enough that a collision at T = 1 takes ~20 steps.
SOFT = """units lj
atom_style sphere
boundary p p p
{processors}
read_data {data}
pair_style gran/hooke 2.0e5 NULL 50.0 NULL 0.0 0
pair_coeff * *
neighbor 0.1 bin
neigh_modify every 1 delay 0 check yes
timestep 5.0e-4
fix nve all nve/sphere
comm_modify vel yes
thermo {steps}
run {steps}
"""

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1")


# The MPI library's own code polls while a rank waits, so its instructions depend on timing: they
# are left out, and what is counted is the work of LAMMPS, the styles and the C library.
MPI_OBJECTS = re.compile(r"libmpi|libopen-pal|libopen-rte|mca_|libucp|libucs|libuct|libpmix|libevent|libhwloc|libfabric")


def self_instructions(path):
    """Self instructions of a callgrind profile outside the MPI objects (a call line's inclusive
    cost, after `calls=`, belongs to the callee and is skipped)."""
    names, ob, skip_next, total = {}, "", False, 0
    for line in Path(path).read_text(errors="replace").splitlines():
        if line.startswith(("ob=", "cob=")):
            # Compressed names are defined where an object first appears, in ob= or in cob= lines.
            key, _, rest = line.partition("=")
            m = re.match(r"\((\d+)\)(?: (.*))?", rest)
            name = rest
            if m:
                if m.group(2):
                    names[m.group(1)] = m.group(2)
                name = names.get(m.group(1), "")
            if key == "ob":
                ob = name
        elif line.startswith("calls="):
            skip_next = True
        elif line[:1].isdigit() or line[:1] in "+-*":
            if skip_next:
                skip_next = False
            elif not MPI_OBJECTS.search(ob):
                parts = line.split()
                if len(parts) >= 2:
                    total += int(parts[1])
    return total


def instructions(out_dir):
    """Instructions of each rank's callgrind profile in out_dir (MPI library left out), in rank order."""
    # One profile per thread: the rank's main thread is -01; the others are the MPI library's
    # progress threads, whose polling depends on timing.
    counts = {int(f.rsplit(".", 1)[1][:-3]): self_instructions(f) for f in glob.glob(str(out_dir / "cg.*-01"))}
    return [counts[r] for r in sorted(counts)]


def run_lammps(lmp, work, template, data, ranks, steps, mpirun, grid, wrap, env):
    """Runs `steps` steps on `ranks` ranks in a new directory under `work`, each rank's command
    prefixed by `wrap`; returns the directory."""
    run_dir = Path(tempfile.mkdtemp(dir=work))
    processors = "processors 2 2 2" if grid and ranks == 8 else ""
    (run_dir / "in.count").write_text(template.format(data=Path(data).resolve(), steps=steps, processors=processors))
    cmd = [mpirun, "-np", str(ranks), "--allow-run-as-root", "--oversubscribe"]
    for name in ("LD_PRELOAD", "HS_MPI_TRAFFIC"):
        if name in env:
            cmd += ["-x", name]
    cmd += wrap + [str(Path(lmp).resolve()), "-in", "in.count", "-log", "none", "-echo", "none", "-screen", "none"]
    harness.run_program(cmd, cwd=run_dir, env=env)
    return run_dir


def count(lmp, work, template, data, ranks, steps, mpirun, grid):
    """Per-rank instructions of one run of `steps` steps."""
    wrap = ["valgrind", "--tool=callgrind", "--separate-threads=yes", "--callgrind-out-file=cg.%q{OMPI_COMM_WORLD_RANK}"]
    return instructions(run_lammps(lmp, work, template, data, ranks, steps, mpirun, grid, wrap, ENV))


def traffic(lmp, work, template, data, ranks, steps, mpirun, grid, interposer):
    """Per-rank [messages, bytes, collective calls] of one run of `steps` steps (the MPI
    profiling interposer of bench/mpi_traffic/)."""
    run_dir = Path(tempfile.mkdtemp(dir=work))
    env = dict(ENV, LD_PRELOAD=str(interposer), HS_MPI_TRAFFIC=str(run_dir / "traffic"))
    run_lammps(lmp, work, template, data, ranks, steps, mpirun, grid, [], env)
    rows = {int(f.rsplit(".", 1)[1]): [int(x) for x in Path(f).read_text().split()[:3]]
            for f in glob.glob(str(run_dir / "traffic.*"))}
    return [rows[r] for r in sorted(rows)]


def difference(f, steps, *args):
    """f's per-rank figures for the steps between the two run lengths."""
    short, long_ = f(*args[:5], steps[0], *args[5:]), f(*args[:5], steps[1], *args[5:])
    sub = lambda a, b: [y - x for x, y in zip(a, b)] if isinstance(a, list) else b - a
    return [sub(a, b) for a, b in zip(short, long_)]


def build_interposer(work, mpicc):
    out = Path(work) / "libmpi_traffic.so"
    src = Path(__file__).resolve().parent / "mpi_traffic" / "mpi_traffic.c"
    harness.run_program([mpicc, "-O2", "-shared", "-fPIC", "-o", out, src])
    return out


def table(rows):
    """One group's rows (same engine, scaling, phi and run lengths), ranks ascending: relative to the
    1-rank row the sum over ranks (strong scaling) or the mean per rank (weak scaling)."""
    weak = bool(rows[0]["weak"])
    lines = ["| spheres | ranks | instructions per step (sum) | " + ("per rank / 1 rank" if weak else "sum / serial")
             + " | busiest / mean | messages per rank per step | kB per rank per step | collective calls per step |",
             "|---|---|---|---|---|---|---|---|"]
    base = next((r["instructions"] for r in rows if r["ranks"] == 1), None)
    for r in rows:
        steps, per_rank, tr = r["steps"][1] - r["steps"][0], r["instructions"], r["traffic"]
        total = sum(per_rank)
        mean = total / len(per_rank)
        rel = "-" if base is None else f"{mean / (sum(base) / len(base)):.2f}" if weak else f"{total / sum(base):.2f}"
        msgs = sum(t[0] for t in tr) / len(tr) / steps
        kb = sum(t[1] for t in tr) / len(tr) / steps / 1e3
        coll = max(t[2] for t in tr) / steps
        grid = " (2 x 2 x 2)" if r["grid"] and r["ranks"] == 8 else ""
        spheres = f"{r['weak']} per rank" if weak else str(r["n"])
        lines.append(f"| {spheres} | {r['ranks']}{grid} | {total / steps / 1e6:.1f}e6 | {rel} | {max(per_rank) / mean:.2f} | "
                     f"{msgs:.1f} | {kb:.1f} | {coll:.1f} |")
    return "\n".join(lines)


def markdown(store):
    rows = store.rows("counts")
    lines = ["# Work counts of fix hardsphere under MPI", "",
             "Instructions per rank (callgrind on a portable build, each rank's main thread, the MPI library's objects "
             "left out) per step, as the difference of two run lengths so that set-up cancels, and each rank's MPI "
             "messages, bytes and collective calls per step (bench/mpi_traffic/). Counts, not timings: they do not "
             "depend on the machine or its load.", "", "Measured by " + "; ".join(harness.measured_by(rows)) + ".", ""]
    groups = {}
    for r in rows:
        groups.setdefault((r["engine"], r["weak"] or r["n"], bool(r["weak"]), r["phi"], tuple(r["steps"]), r["grid"]),
                          []).append(r)
    for (engine, size, weak, phi, steps, _), rs in groups.items():
        what = f"weak scaling, {size} spheres per rank" if weak else f"{size} spheres"
        lines += [f"## {engine}: {what}, phi {phi}, steps {steps[0]} to {steps[1]}", "",
                  table(sorted(rs, key=lambda r: r["ranks"])), ""]
    return "\n".join(lines)


def write_state(hs, n, phi, path):
    harness.run_program([hs, "run", "--n", n, "--phi", phi, "--steps", 100, "--quiet", "--write-data", path])


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere", "lmp_hs", "mpirun"))
    ap.add_argument("--mpicc", default="mpicc")
    ap.add_argument("--n", type=int, default=256000)
    ap.add_argument("--phi", type=float, default=0.3)
    ap.add_argument("--ranks", type=int, nargs="+", default=[2, 4, 8])
    ap.add_argument("--steps", type=int, nargs=2, default=[10, 50], help="the two run lengths")
    ap.add_argument("--grid", action="store_true", help="8 ranks as 2 x 2 x 2 (else LAMMPS's choice)")
    ap.add_argument("--weak", type=int, default=0, help="spheres per rank: weak scaling instead of --n")
    ap.add_argument("--no-peer", action="store_true", help="skip gran/hooke")
    ap.add_argument("--peer-only", action="store_true", help="only gran/hooke")
    ap.add_argument("--cache", help="JSON file keeping each finished row, reused by the next call")
    ap.add_argument("--from-json", action="store_true", help="render DIR/lammps_work_counts.md from its JSON only")
    a = ap.parse_args(argv)
    session = harness.Session("bench.lammps_work_counts", a, argv)
    store = harness.RowStore(session.out(), "lammps_work_counts")
    if a.from_json:
        return session.finish([], store.render(markdown(store)))
    tools = harness.tools(a, need=("hardsphere", "lmp_hs", "mpirun", "valgrind"))
    cache = json.loads(Path(a.cache).read_text()) if a.cache and Path(a.cache).exists() else {}
    ranks = sorted(set([1] + a.ranks))
    with session.workdir() as work:
        interposer = build_interposer(work, a.mpicc)
        states = {}
        for r in ranks:
            n = a.weak * r if a.weak else a.n
            if n not in states:
                states[n] = work / f"state{n}.data"
                write_state(tools["hardsphere"], n, a.phi, states[n])
        engines = ([] if a.peer_only else [("fix hardsphere", HARD)]) + ([] if a.no_peer else [("gran/hooke", SOFT)])
        for name, template in engines:
            for r in ranks:
                key = f"{name}|{a.weak * r if a.weak else a.n}|{a.phi}|{r}|{a.grid}|{a.steps}"
                if key not in cache:
                    data = states[a.weak * r if a.weak else a.n]
                    args = (tools["lmp_hs"], work, template, data, r, tools["mpirun"], a.grid)
                    cache[key] = [difference(count, a.steps, *args), difference(traffic, a.steps, *args, interposer)]
                    if a.cache:
                        Path(a.cache).write_text(json.dumps(cache))
                instructions_, traffic_ = cache[key]
                store.put("counts", key, dict(engine=name, n=a.weak * r if a.weak else a.n, weak=a.weak, phi=a.phi,
                                              ranks=r, grid=a.grid, steps=a.steps, instructions=instructions_,
                                              traffic=traffic_), session)
                session.log(f"{name}, {r} ranks: {sum(instructions_) / (a.steps[1] - a.steps[0]) / 1e6:.1f}e6 "
                            "instructions per step")
    return session.finish([], store.render(markdown(store)))


if __name__ == "__main__":
    harness.main(main)
