#!/usr/bin/env python3
"""Run time against error: the exact event-driven engine as the reference for the time stepper.

Subcommands (default: accuracy):
  accuracy  For one initial state per packing fraction (N spheres, equilibrated with the event
            engine), run the event engine as reference and the stepper over a dt sweep in
            double and float precision and with both contact detections (overlap, sweep).
            Report CPU seconds per unit of simulated time, relative errors in Z and in the
            collision rate, energy drift, the collision-rate deficit, KS distance of the speeds
            from Maxwell-Boltzmann. Writes accuracy.md, accuracy.json and accuracy.png, plus the
            "time to accuracy" table (cheapest setting within 1% of the precise Z) at N = 8000.
  eos       Z and the collision rate of the event engine against Carnahan-Starling, Kolafa's
            correction and Enskog, with block-average error bars (eos.md, eos.json).
  speed     Event-engine collisions per second against N (speed.md, speed.json).

All numbers come from `hardsphere run --json -`; every state is written with --write-data and
read back with --read-data, so every engine starts from exactly the same spheres.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path


def z_cs(eta):
    """Carnahan-Starling."""
    return (1 + eta + eta**2 - eta**3) / (1 - eta) ** 3


def z_kolafa(eta):
    """Kolafa's correction to CS (Boublik & Nezbeda, Collect. Czech. Chem. Commun. 51, 2301 (1986))."""
    return (1 + eta + eta**2 - 2.0 / 3.0 * eta**3 * (1 + eta)) / (1 - eta) ** 3


def enskog_rate(eta, z, temperature=1.0, mass=1.0):
    """Enskog collisions per particle per unit time, sigma = 1, with g(sigma) = (Z - 1)/(4 eta)."""
    n = 6 * eta / math.pi
    g = (z - 1) / (4 * eta)
    return 4 * n * math.sqrt(math.pi * temperature / mass) * g


class Runner:
    def __init__(self, hs, out, verbose=True):
        self.hs = str(hs)
        self.out = Path(out)
        self.out.mkdir(parents=True, exist_ok=True)
        self.verbose = verbose

    def run(self, *args):
        cmd = [self.hs, "run", *map(str, args), "--json", "-"]
        t0 = time.time()
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}): {p.stderr.strip()}")
        j = json.loads(p.stdout)
        if self.verbose:
            print(f"  [{time.time() - t0:6.1f} s] {' '.join(map(str, args))}", file=sys.stderr, flush=True)
        return j

    def state(self, n, phi, equilibrate, seed=1):
        """An equilibrated state (generated, then equilibrated with the event engine), cached."""
        final = self.out / f"state_n{n}_phi{phi}_seed{seed}.data"
        if final.exists():
            return final
        raw = self.out / f"raw_n{n}_phi{phi}_seed{seed}.data"
        if not raw.exists():  # a raw state may be provided (large N takes a while to generate)
            self.run("--n", n, "--phi", phi, "--seed", seed, "--steps", 0, "--write-data", raw)
        self.run("--engine", "event", "--read-data", raw, "--time", equilibrate, "--blocks", 1, "--write-data", final)
        raw.unlink()
        return final


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------------------- eos
def cmd_eos(args):
    r = Runner(args.hardsphere, args.out)
    rows, data = [], []
    for phi in args.phi:
        s = r.state(args.n, phi, args.equilibrate)
        # Enough time for ~args.collisions collisions (rate estimated from Enskog with Kolafa's g).
        rate = enskog_rate(phi, z_kolafa(phi))
        t = args.collisions / (args.n * rate / 2)
        j = r.run("--engine", "event", "--read-data", s, "--time", f"{t:.6g}", "--blocks", args.blocks)
        z, dz = j["compressibility_factor"], j["compressibility_factor_error"]
        g, dg = j["collision_rate_per_particle"], j["collision_rate_error"]
        zk, zc = z_kolafa(phi), z_cs(phi)
        ens = enskog_rate(phi, zc)  # Enskog with the CS contact value
        d = dict(phi=phi, n=args.n, time=t, collisions=j["collisions"], z=z, z_err=dz, z_cs=zc, z_kolafa=zk,
                 rate=g, rate_err=dg, rate_enskog_cs=ens, collisions_per_second=j["collisions_per_second"],
                 energy_rel_drift=j["energy_rel_drift"], max_overlap=j["max_overlap"])
        data.append(d)
        rows.append([phi, f"{z:.4f} ± {dz:.4f}", f"{zc:.4f}", f"{100 * (z / zc - 1):+.2f}%", f"{zk:.4f}",
                     f"{100 * (z / zk - 1):+.2f}%", f"{g:.4f} ± {dg:.4f}", f"{ens:.4f}", f"{100 * (g / ens - 1):+.2f}%",
                     f"{j['collisions']:.3g}"])
    text = (f"Event engine, N = {args.n}, each state equilibrated for {args.equilibrate} time units, then about "
            f"{args.collisions:.3g} collisions measured in {args.blocks} blocks (error = standard error of the block means). "
            "Units: sigma = m = kT = 1.\n\n" +
            md_table(["phi", "Z measured", "Z_CS", "vs CS", "Z_Kolafa", "vs Kolafa", "collision rate", "Enskog (g_CS)",
                      "vs Enskog", "collisions"], rows))
    (Path(args.out) / "eos.md").write_text(text)
    (Path(args.out) / "eos.json").write_text(json.dumps(data, indent=2))
    print(text)


# --------------------------------------------------------------------------------------- speed
def cmd_speed(args):
    r = Runner(args.hardsphere, args.out)
    rows, data = [], []
    for n in args.n:
        s = r.state(n, args.phi, args.equilibrate)
        rate = enskog_rate(args.phi, z_kolafa(args.phi))
        t = max(args.collisions / (n * rate / 2), 0.05)
        j = r.run("--engine", "event", "--read-data", s, "--time", f"{t:.6g}", "--blocks", 1)
        d = dict(n=n, phi=args.phi, time=t, collisions=j["collisions"], cpu=j["loop_cpu_seconds"],
                 collisions_per_second=j["collisions_per_second"], events_per_second=j["events_per_second"],
                 cells_per_dim=j["cells_per_dim"])
        data.append(d)
        rows.append([n, args.phi, f"{j['collisions']:.3g}", f"{j['loop_cpu_seconds']:.2f}",
                     f"{j['collisions_per_second']:.3g}", f"{j['events_per_second']:.3g}"])
    text = (f"Event engine, packing fraction {args.phi}, one thread, equilibrated states, about {args.collisions:.3g} "
            "collisions per run (CPU time of the event loop only).\n\n" +
            md_table(["N", "phi", "collisions", "CPU s", "collisions/s", "events/s"], rows))
    (Path(args.out) / "speed.md").write_text(text)
    (Path(args.out) / "speed.json").write_text(json.dumps(data, indent=2))
    print(text)


# ------------------------------------------------------------------------------------ accuracy
def stepper_modes(args):
    modes = []
    for precision in args.precision:
        for detect in args.detect:
            modes.append((precision, detect))
    return modes


def sweep(r, n, phi, args, dts):
    """Reference and stepper runs on one state; returns the rows (dicts)."""
    s = r.state(n, phi, args.equilibrate)
    ref = r.run("--engine", "event", "--read-data", s, "--time", args.time, "--blocks", args.blocks)
    z_ref, dz_ref = ref["compressibility_factor"], ref["compressibility_factor_error"]
    g_ref = ref["collision_rate_per_particle"]
    rows = [dict(n=n, phi=phi, engine="event", precision="double", detect="exact", dt=None,
                 cpu_per_time=ref["loop_cpu_seconds"] / ref["sim_time"], z=z_ref, z_err=dz_ref, z_rel_err=0.0,
                 rate=g_ref, rate_rel_err=0.0, energy_rel_drift=ref["energy_rel_drift"], rate_deficit=0.0,
                 ks=ref["speed_ks_distance"], max_overlap=ref["max_overlap"], z_ref=z_ref, z_ref_err=dz_ref,
                 z_kolafa=z_kolafa(phi))]
    for precision, detect in stepper_modes(args):
        for dt in dts:
            try:
                j = r.run("--read-data", s, "--time", args.time, "--dt", dt, "--precision", precision, "--detect", detect)
            except RuntimeError as e:  # e.g. a step too long for the scene: record and go on
                print(f"  skipped: {e}", file=sys.stderr)
                continue
            z, g = j["compressibility_factor"], j["collision_rate_per_particle"]
            rows.append(dict(n=n, phi=phi, engine="stepper", precision=precision, detect=detect, dt=dt,
                             cpu_per_time=j["loop_cpu_seconds"] / j["sim_time"], z=z, z_err=None,
                             z_rel_err=z / z_ref - 1, rate=g, rate_rel_err=g / g_ref - 1,
                             energy_rel_drift=j["energy_rel_drift"], rate_deficit=1 - g / g_ref,
                             ks=j["speed_ks_distance"], max_overlap=j["max_overlap"], z_ref=z_ref, z_ref_err=dz_ref,
                             z_kolafa=z_kolafa(phi), mean_free_times_per_step=dt * g_ref))
    return rows


def fmt_rows(rows):
    out = []
    for d in rows:
        out.append([d["phi"], d["engine"], d["precision"], d["detect"], "-" if d["dt"] is None else d["dt"],
                    "-" if d["dt"] is None else f"{d['mean_free_times_per_step']:.3f}",
                    f"{d['cpu_per_time']:.4g}", f"{d['z']:.4f}", f"{100 * d['z_rel_err']:+.2f}%",
                    f"{100 * d['rate_rel_err']:+.2f}%", f"{d['energy_rel_drift']:.1e}", f"{d['ks']:.4f}",
                    f"{d['max_overlap']:.1e}"])
    return out


HEADER = ["phi", "engine", "precision", "detect", "dt", "dt/mean free time", "CPU s per unit time", "Z",
          "Z rel. error", "collision rate rel. error (= minus the deficit)", "energy drift", "KS distance",
          "max overlap"]


def plot(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    phis = sorted({d["phi"] for d in rows})
    fig, axes = plt.subplots(1, len(phis), figsize=(5 * len(phis), 4.2), squeeze=False)
    for ax, phi in zip(axes[0], phis):
        sub = [d for d in rows if d["phi"] == phi]
        ref = [d for d in sub if d["engine"] == "event"][0]
        floor = max(ref["z_err"] / ref["z"], 1e-5)
        keys = sorted({(d["precision"], d["detect"]) for d in sub if d["engine"] == "stepper"})
        for k in keys:
            c = sorted([d for d in sub if (d["precision"], d["detect"]) == k], key=lambda d: d["dt"])
            x = [d["cpu_per_time"] for d in c]
            y = [max(abs(d["z_rel_err"]), floor / 10) for d in c]
            line, = ax.loglog(x, y, "o-", lw=0.8, label=f"stepper {k[0]} {k[1]} (dt increasing along the line)")
            for d, xi, yi in zip(c, x, y):
                ax.annotate(f"{d['dt']:g}", (xi, yi), fontsize=6, color=line.get_color(), xytext=(2, 2),
                            textcoords="offset points")
        ax.loglog([ref["cpu_per_time"]], [floor], "k*", ms=12, label="event engine (plotted at its error bar)")
        ax.axhline(0.01, color="grey", ls=":", lw=1)
        ax.axhspan(floor / 10, 2 * floor, color="grey", alpha=0.15, lw=0, label="statistical noise (< 2 error bars)")
        ax.set_xlabel("CPU s per unit simulated time")
        ax.set_ylabel("|relative error of Z|")
        ax.set_title(f"{title}, phi = {phi}")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def time_to_accuracy(rows, tol=0.01):
    out = []
    for phi in sorted({d["phi"] for d in rows}):
        sub = [d for d in rows if d["phi"] == phi]
        ok = [d for d in sub if abs(d["z_rel_err"]) <= tol]
        best = min(ok, key=lambda d: d["cpu_per_time"])
        ev = [d for d in sub if d["engine"] == "event"][0]
        out.append(dict(phi=phi, n=best["n"], best=best, event=ev))
    return out


def cmd_accuracy(args):
    r = Runner(args.hardsphere, args.out)
    rows = []
    for phi in args.phi:
        rows += sweep(r, args.n, phi, args, args.dt)
    text = (f"N = {args.n}, simulated time {args.time} per run after {args.equilibrate} units of event-driven "
            f"equilibration; reference = event engine on the same state (Z error bar from {args.blocks} blocks). "
            "The stepper's Z carries a statistical error of about the reference's error bar (same N and run length), "
            "so |Z error| below ~2x that bar is noise. The collision-rate error is also the estimate of missed (-) "
            "or spurious (+) collisions: 1 - rate/exact rate.\n\n" + md_table(HEADER, fmt_rows(rows)))
    if args.tta_n:
        tta_rows = []
        for phi in args.tta_phi:
            tta_rows += sweep(r, args.tta_n, phi, args, args.tta_dt)
        text += (f"\n### Time to accuracy (N = {args.tta_n})\n\nCheapest setting whose Z is within 1% of the event "
                 "engine's Z on the same state (CPU seconds per unit of simulated time, one thread).\n\n")
        tab = []
        for t in time_to_accuracy(tta_rows):
            b, e = t["best"], t["event"]
            tab.append([t["phi"], f"{b['engine']} {b['precision']} {b['detect']} dt={b['dt']}", f"{b['cpu_per_time']:.4g}",
                        f"{100 * b['z_rel_err']:+.2f}%", f"{e['cpu_per_time']:.4g}",
                        f"{e['z']:.4f} ± {e['z_err']:.4f}"])
        text += md_table(["phi", "cheapest within 1%", "CPU s / unit time", "Z error", "event engine CPU s / unit time",
                          "precise Z (event)"], tab)
        text += "\nAll settings at this N:\n\n" + md_table(HEADER, fmt_rows(tta_rows))
        rows_all = rows + tta_rows
        plot(tta_rows, Path(args.out) / "time_to_accuracy.png", f"N = {args.tta_n}")
    else:
        rows_all = rows
    (Path(args.out) / "accuracy.md").write_text(text)
    (Path(args.out) / "accuracy.json").write_text(json.dumps(rows_all, indent=2))
    plot(rows, Path(args.out) / "accuracy.png", f"N = {args.n}")
    print(text)


def main(argv=None):
    here = Path(__file__).resolve().parent.parent
    default_hs = here / "build" / "standalone" / "hardsphere"
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("command", nargs="?", default="accuracy", choices=["accuracy", "eos", "speed", "plot"])
    p.add_argument("--hardsphere", default=os.environ.get("HARDSPHERE", str(default_hs)), help="path of the hardsphere program")
    p.add_argument("--out", default="accuracy_out", help="output directory (states are cached there)")
    p.add_argument("--quick", action="store_true", help="small fast smoke version (N = 1000, one density)")
    p.add_argument("--n", type=int, nargs="+", default=None, help="spheres (speed: a list)")
    p.add_argument("--phi", type=float, nargs="+", default=None)
    p.add_argument("--time", type=float, default=5.0, help="simulated time per accuracy run")
    p.add_argument("--equilibrate", type=float, default=None,
                   help="event-engine equilibration of each state (default 5; speed: 0.5)")
    p.add_argument("--blocks", type=int, default=20)
    p.add_argument("--dt", type=float, nargs="+", default=[0.001, 0.002, 0.005, 0.01, 0.02, 0.04])
    p.add_argument("--precision", nargs="+", default=["double", "float"])
    p.add_argument("--detect", nargs="+", default=["overlap", "sweep"])
    p.add_argument("--tta-n", type=int, default=8000, help="N of the time-to-accuracy sweep (0: skip)")
    p.add_argument("--tta-phi", type=float, nargs="+", default=[0.30, 0.45])
    p.add_argument("--tta-dt", type=float, nargs="+", default=[0.005, 0.01, 0.02, 0.03, 0.04, 0.06])
    p.add_argument("--collisions", type=float, default=None, help="eos/speed: collisions per run")
    a = p.parse_args(argv)
    if a.command == "plot":  # re-draw the figures from accuracy.json in --out
        rows = json.loads((Path(a.out) / "accuracy.json").read_text())
        for n in sorted({d["n"] for d in rows}):
            name = "time_to_accuracy.png" if n == a.tta_n else "accuracy.png"
            plot([d for d in rows if d["n"] == n], Path(a.out) / name, f"N = {n}")
        return
    if not Path(a.hardsphere).exists():
        p.error(f"--hardsphere {a.hardsphere} does not exist")
    if a.equilibrate is None:
        a.equilibrate = 0.5 if a.command == "speed" else 5.0
    if a.command == "accuracy":
        a.n = (a.n or [10000])[0]
        a.phi = a.phi or [0.1, 0.3, 0.45]
        if a.quick:
            a.n, a.phi, a.time, a.equilibrate, a.blocks = 1000, [0.3], 1.0, 1.0, 10
            a.dt, a.tta_n, a.precision = [0.005, 0.02], 1000, ["double", "float"]
            a.tta_phi, a.tta_dt = [0.3], [0.01, 0.04]
        cmd_accuracy(a)
    elif a.command == "eos":
        a.n = (a.n or [4000])[0]
        a.phi = a.phi or [0.1, 0.2, 0.3, 0.35, 0.4, 0.45]
        a.collisions = a.collisions or 4e6
        if a.quick:
            a.n, a.phi, a.collisions, a.equilibrate = 1000, [0.3], 1e5, 1.0
        cmd_eos(a)
    else:
        a.n = a.n or [1000, 4000, 32000, 256000, 1000000]
        a.phi = (a.phi or [0.45])[0]
        a.collisions = a.collisions or 3e6
        if a.quick:
            a.n, a.collisions, a.equilibrate = [1000, 4000], 1e5, 1.0
        cmd_speed(a)


if __name__ == "__main__":
    main()
