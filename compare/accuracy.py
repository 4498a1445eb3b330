#!/usr/bin/env python3
"""Run time against error: the exact event-driven engine as the reference for the time stepper.

  python3 -m compare.accuracy [accuracy|eos|speed|report] --out DIR [--quick] [--build DIR]
      [--hardsphere PATH] [--work DIR] [options of the sweep]

Subcommands (default: accuracy):
  accuracy  For one initial state per packing fraction (N spheres, equilibrated with the event
            engine), run the event engine as reference and the stepper over a dt sweep in
            double and float precision and with both contact detections (overlap, sweep).
            Report CPU seconds per unit of simulated time, relative errors in Z and in the
            collision rate, energy drift, the collision-rate deficit, KS distance of the speeds
            from Maxwell-Boltzmann. Writes accuracy.md, accuracy.json and accuracy.png, plus the
            "time to accuracy" table (cheapest setting within 1% of the precise Z, beside the best
            published event-driven code) at N = 8000 and time_to_accuracy.png.
  eos       Z and the collision rate of the event engine against Carnahan-Starling, Kolafa's
            correction and Enskog, with block-average error bars (eos.md, eos.json).
  speed     Event-engine collisions per second against N (speed.md, speed.json).
  report    No runs: eos.md and speed.md and the two figures again from the JSON files in --out
            (`--out docs/reports/event_engine` for the committed ones; --accuracy-md rewrites
            accuracy.md too).

All numbers come from `hardsphere run --json -`; every state is written with --write-data and
read back with --read-data, so every engine starts from exactly the same spheres. The states are
made in --work (kept there and reused by the next subcommand with that --work). The report
writers: compare.accuracy_report; the formulas: compare.hard_sphere_theory.
"""
import json
from pathlib import Path

from compare import accuracy_report as report
from compare import hard_sphere_theory as hs_theory
from compare import harness


class Runner:
    def __init__(self, hs, work, log):
        self.hs, self.work, self.log = str(hs), Path(work), log

    def run(self, *args):
        j = harness.hardsphere_json(self.hs, *map(str, args))
        self.log(" ".join(map(str, args)))
        return j

    def state(self, n, phi, equilibrate, seed=1):
        """An equilibrated state (generated, then equilibrated with the event engine), cached in --work."""
        final = self.work / f"state_n{n}_phi{phi}_seed{seed}.data"
        if final.exists():
            return final
        raw = self.work / f"raw_n{n}_phi{phi}_seed{seed}.data"
        if not raw.exists():  # a raw state may be provided (large N takes a while to generate)
            self.run("--n", n, "--phi", phi, "--seed", seed, "--steps", 0, "--write-data", raw)
        self.run("--engine", "event", "--read-data", raw, "--time", equilibrate, "--blocks", 1, "--write-data", final)
        raw.unlink()
        return final


# ----------------------------------------------------------------------------------------- eos
def cmd_eos(args, r):
    data = []
    for phi in args.phi:
        s = r.state(args.n, phi, args.equilibrate)
        # Enough time for ~args.collisions collisions (rate estimated from Enskog with Kolafa's g).
        rate = hs_theory.enskog_rate_from_z(phi, hs_theory.z_kolafa(phi))
        t = args.collisions / (args.n * rate / 2)
        j = r.run("--engine", "event", "--read-data", s, "--time", f"{t:.6g}", "--blocks", args.blocks)
        zc = hs_theory.z_carnahan_starling(phi)
        data.append(dict(phi=phi, n=args.n, time=t, collisions=j["collisions"], z=j["compressibility_factor"],
                         z_err=j["compressibility_factor_error"], z_cs=zc, z_kolafa=hs_theory.z_kolafa(phi),
                         rate=j["collision_rate_per_particle"], rate_err=j["collision_rate_error"],
                         rate_enskog_cs=hs_theory.enskog_rate_from_z(phi, zc),  # Enskog with the CS contact value
                         collisions_per_second=j["collisions_per_second"], energy_rel_drift=j["energy_rel_drift"],
                         max_overlap=j["max_overlap"], equilibrate=args.equilibrate, blocks=args.blocks))
    return "eos", data, report.eos_markdown(data, args.generated())


# --------------------------------------------------------------------------------------- speed
def cmd_speed(args, r):
    data = []
    for n in args.n:
        s = r.state(n, args.phi, args.equilibrate)
        rate = hs_theory.enskog_rate_from_z(args.phi, hs_theory.z_kolafa(args.phi))
        t = max(args.collisions / (n * rate / 2), 0.05)
        j = r.run("--engine", "event", "--read-data", s, "--time", f"{t:.6g}", "--blocks", 1)
        data.append(dict(n=n, phi=args.phi, time=t, collisions=j["collisions"], cpu=j["loop_cpu_seconds"],
                         collisions_per_second=j["collisions_per_second"], events_per_second=j["events_per_second"],
                         cells_per_dim=j["cells_per_dim"], equilibrate=args.equilibrate))
    return "speed", data, report.speed_markdown(data, args.generated())


# ------------------------------------------------------------------------------------ accuracy
def sweep(r, n, phi, args, dts):
    """Reference and stepper runs on one state; returns the rows (dicts)."""
    s = r.state(n, phi, args.equilibrate)
    ref = r.run("--engine", "event", "--read-data", s, "--time", args.time, "--blocks", args.blocks)
    z_ref, dz_ref = ref["compressibility_factor"], ref["compressibility_factor_error"]
    g_ref = ref["collision_rate_per_particle"]
    common = dict(n=n, phi=phi, z_ref=z_ref, z_ref_err=dz_ref, z_kolafa=hs_theory.z_kolafa(phi), time=args.time,
                  equilibrate=args.equilibrate, blocks=args.blocks)
    rows = [dict(common, engine="event", precision="double", detect="exact", dt=None,
                 cpu_per_time=ref["loop_cpu_seconds"] / ref["sim_time"], z=z_ref, z_err=dz_ref, z_rel_err=0.0,
                 rate=g_ref, rate_rel_err=0.0, energy_rel_drift=ref["energy_rel_drift"], rate_deficit=0.0,
                 ks=ref["speed_ks_distance"], max_overlap=ref["max_overlap"])]
    for precision in args.precision:
        for detect in args.detect:
            for dt in dts:
                try:
                    j = r.run("--read-data", s, "--time", args.time, "--dt", dt, "--precision", precision,
                              "--detect", detect)
                except harness.ProgramError as e:  # e.g. a step too long for the scene: record and go on
                    r.log(f"skipped: {e}")
                    continue
                z, g = j["compressibility_factor"], j["collision_rate_per_particle"]
                rows.append(dict(common, engine="stepper", precision=precision, detect=detect, dt=dt,
                                 cpu_per_time=j["loop_cpu_seconds"] / j["sim_time"], z=z, z_err=None,
                                 z_rel_err=z / z_ref - 1, rate=g, rate_rel_err=g / g_ref - 1,
                                 energy_rel_drift=j["energy_rel_drift"], rate_deficit=1 - g / g_ref,
                                 ks=j["speed_ks_distance"], max_overlap=j["max_overlap"],
                                 mean_free_times_per_step=dt * g_ref))
    return rows


def cmd_accuracy(args, r):
    rows = []
    for phi in args.phi:
        rows += sweep(r, args.n, phi, args, args.dt)
    tta_rows = []
    if args.tta_n:
        for phi in args.tta_phi:
            tta_rows += sweep(r, args.tta_n, phi, args, args.tta_dt)
        report.plot(tta_rows, Path(args.out) / "time_to_accuracy.png", f"N = {args.tta_n}")
    report.plot(rows, Path(args.out) / "accuracy.png", f"N = {args.n}")
    return "accuracy", rows + tta_rows, report.accuracy_markdown(rows, tta_rows, args.generated())


def main(argv=None):
    ap = harness.parser(__doc__, programs=("hardsphere",), work=True)
    ap.add_argument("command", nargs="?", default="accuracy", choices=["accuracy", "eos", "speed", "report"])
    ap.add_argument("--quick", action="store_true", help="small fast smoke version (N = 1000, one density)")
    ap.add_argument("--n", type=int, nargs="+", default=None, help="spheres (speed: a list)")
    ap.add_argument("--phi", type=float, nargs="+", default=None)
    ap.add_argument("--time", type=float, default=5.0, help="simulated time per accuracy run")
    ap.add_argument("--equilibrate", type=float, default=None,
                    help="event-engine equilibration of each state (default 5; speed: 0.5)")
    ap.add_argument("--blocks", type=int, default=20)
    ap.add_argument("--dt", type=float, nargs="+", default=[0.001, 0.002, 0.005, 0.01, 0.02, 0.04])
    ap.add_argument("--precision", nargs="+", default=["double", "float"])
    ap.add_argument("--detect", nargs="+", default=["overlap", "sweep"])
    ap.add_argument("--tta-n", type=int, default=8000, help="N of the time-to-accuracy sweep (0: skip)")
    ap.add_argument("--tta-phi", type=float, nargs="+", default=[0.30, 0.45])
    ap.add_argument("--tta-dt", type=float, nargs="+", default=[0.005, 0.01, 0.02, 0.03, 0.04, 0.06])
    ap.add_argument("--collisions", type=float, default=None, help="eos/speed: collisions per run")
    ap.add_argument("--accuracy-md", action="store_true", help="report: rewrite accuracy.md from accuracy.json too")
    a = ap.parse_args(argv)
    session = harness.Session("compare.accuracy", a, argv)
    out = session.out()
    if a.command == "report":  # no runs: the reports again from the JSON in --out
        for path in report.from_json(out, write_accuracy=a.accuracy_md):
            session.log(f"wrote {path}")
        return session.finish([])
    hs = harness.tools(a, need=("hardsphere",))["hardsphere"]
    if a.equilibrate is None:
        a.equilibrate = 0.5 if a.command == "speed" else 5.0
    if a.command == "accuracy":
        a.n = (a.n or [10000])[0]
        a.phi = a.phi or [0.1, 0.3, 0.45]
        if a.quick:
            a.n, a.phi, a.time, a.equilibrate, a.blocks = 1000, [0.3], 1.0, 1.0, 10
            a.dt, a.tta_n, a.precision = [0.005, 0.02], 1000, ["double", "float"]
            a.tta_phi, a.tta_dt = [0.3], [0.01, 0.04]
        command = cmd_accuracy
    elif a.command == "eos":
        a.n = (a.n or [4000])[0]
        a.phi = a.phi or [0.1, 0.2, 0.3, 0.35, 0.4, 0.45]
        a.collisions = a.collisions or 4e6
        if a.quick:
            a.n, a.phi, a.collisions, a.equilibrate = 1000, [0.3], 1e5, 1.0
        command = cmd_eos
    else:
        a.n = a.n or [1000, 4000, 32000, 256000, 1000000]
        a.phi = (a.phi or [0.45])[0]
        a.collisions = a.collisions or 3e6
        if a.quick:
            a.n, a.collisions, a.equilibrate = [1000, 4000], 1e5, 1.0
        command = cmd_speed
    a.generated = session.generated
    with session.workdir() as work:
        stem, data, text = command(a, Runner(hs, work, session.log))
    (out / f"{stem}.json").write_text(json.dumps(data, indent=2))
    path = session.write_report(out, stem, text)
    return session.finish([], path)


if __name__ == "__main__":
    harness.main(main)
