#!/usr/bin/python3
"""A model of fix hardsphere's owned + ghost path on many ranks, calibrated by the work counts of
bench/lammps_work_counts.py, with a network of given latency and bandwidth. Prints, per number of
ranks P (cubic sub-domains), the spheres and ghosts per rank, the time per step split into the
work on held spheres, the per-step overhead, latency and bandwidth, and the parallel efficiency;
beside it the same for a path that does not advance its ghosts (each rank advances its owned
spheres and exchanges a boundary layer one contact distance thick, docs/dev/mpi.md), with the
same messages.

  python3 -m bench.mpi_model [--n 1000000] [--phi 0.3] [--latency 1.5e-6] [--bandwidth 1e10]

Defaults: unit spheres at phi 0.3, T = 1, dt = 0.01 (docs/lammps.md, "Many ranks"): 41 ns per
sphere-step of the serial stepper; per held sphere (owned or ghost) 1.18 serial sphere-steps
(the stepper and its re-making at re-neighbourings) and per owned sphere 0.05 more, the two
figures that reproduce the counts at 256000 spheres on 2 ranks (1.48x) and on 2 x 2 x 2 (2.14x);
48 bytes per ghost per step; 12 messages and 3 reductions per step.
"""
import argparse
import math


def ghosts_of(n_rank, rho, shell):
    side = (n_rank / rho) ** (1 / 3)
    return rho * ((side + 2 * shell) ** 3 - side ** 3)


def network(a, ghosts, ranks):
    # Per step: LAMMPS's positions and the fix's velocities to 6 neighbours, three reductions.
    latency = a.latency * (12 + 3 * math.log2(ranks))
    return latency, a.bytes_per_ghost * ghosts / a.bandwidth


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=float, default=1e6, help="spheres in the whole run")
    ap.add_argument("--phi", type=float, default=0.3)
    ap.add_argument("--ranks", type=int, nargs="+", default=[8, 64, 125, 216, 512, 1000])
    ap.add_argument("--latency", type=float, default=1.5e-6, help="seconds per message")
    ap.add_argument("--bandwidth", type=float, default=1e10, help="bytes per second per rank")
    ap.add_argument("--tau", type=float, default=41e-9, help="seconds per sphere-step of the serial stepper")
    ap.add_argument("--held", type=float, default=1.18, help="sphere-steps per held sphere and step")
    ap.add_argument("--overhead", type=float, default=0.05, help="sphere-steps of overhead per owned sphere")
    ap.add_argument("--bytes-per-ghost", type=float, default=48.0)
    ap.add_argument("--shell", type=float, default=4.0, help="ghost shell (diameters): 3 contacts + 2 skins")
    ap.add_argument("--layer", type=float, default=1.1, help="boundary layer without advanced ghosts (d)")
    a = ap.parse_args()
    rho = a.phi / (math.pi / 6)  # unit diameters
    serial = a.tau * a.n
    print(f"# {a.n:.0f} spheres at phi {a.phi}; serial step {serial * 1e3:.2f} ms; latency {a.latency * 1e6:g} us, "
          f"{a.bandwidth / 1e9:g} GB/s; ghost shell {a.shell:g} d")
    print("| ranks | spheres per rank | ghosts per rank | held spheres (us) | overhead (us) | latency (us) | "
          "bandwidth (us) | efficiency | without advancing ghosts |")
    print("|---|---|---|---|---|---|---|---|---|")
    for p in a.ranks:
        n = a.n / p
        ghosts = ghosts_of(n, rho, a.shell)
        held, over = a.tau * a.held * (n + ghosts), a.tau * a.overhead * n
        lat, bw = network(a, ghosts, p)
        eff = serial / p / (held + over + lat + bw)
        # Owned spheres only, a thin layer of copies exchanged, the same messages.
        layer = ghosts_of(n, rho, a.layer)
        lat_l, bw_l = network(a, layer, p)
        eff_lean = serial / p / (a.tau * (n + a.overhead * n) + lat_l + bw_l)
        print(f"| {p} | {n:.0f} | {ghosts:.0f} | {held * 1e6:.0f} | {over * 1e6:.0f} | {lat * 1e6:.1f} | "
              f"{bw * 1e6:.1f} | {eff:.0%} | {eff_lean:.0%} |")


if __name__ == "__main__":
    main()
