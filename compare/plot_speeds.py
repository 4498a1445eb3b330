#!/usr/bin/env python3
"""Speed distribution of a hardsphere/LAMMPS data file against Maxwell-Boltzmann.

  python3 -m compare.plot_speeds STATE.data OUT.png
Speeds are scaled by sqrt(m/T) (T = <m v^2>/3), so mixed masses share one curve.
Prints the Kolmogorov-Smirnov distance and p-value (scipy) against the Maxwell distribution.
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from scipy import stats

from compare import harness
from compare.lammps_files import read_data


def plot(data_path, png_path):
    """Draws the figure; returns the KS test."""
    d = read_data(data_path)
    m, v = d.mass, d.vel
    temperature = np.mean(m * np.sum(v * v, axis=1)) / 3.0
    u = np.linalg.norm(v, axis=1) * np.sqrt(m / temperature)
    ks = stats.kstest(u, stats.maxwell.cdf)
    grid = np.linspace(0, max(5.0, u.max()), 400)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.hist(u, bins=50, density=True, alpha=0.6, label=f"simulation, N = {len(u)}")
    ax.plot(grid, stats.maxwell.pdf(grid), "k-", label="Maxwell-Boltzmann")
    ax.set_xlabel(r"scaled speed $|v|\,\sqrt{m/T}$")
    ax.set_ylabel("probability density")
    ax.set_title(f"T = {temperature:.4f}; KS distance {ks.statistic:.4f}, p = {ks.pvalue:.3f}")
    ax.legend()
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)
    print(f"plot_speeds: T = {temperature:.6f}, KS distance {ks.statistic:.5f}, p = {ks.pvalue:.4f} -> {png_path}")
    return ks


def main(argv=None):
    ap = harness.parser(__doc__, out=False)
    ap.add_argument("data", help="a LAMMPS data file")
    ap.add_argument("png", help="the figure to write")
    a = ap.parse_args(argv)
    plot(a.data, a.png)
    return 0


if __name__ == "__main__":
    harness.main(main)
