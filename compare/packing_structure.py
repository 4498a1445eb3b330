#!/usr/bin/python3
"""Structure of a packing of equal spheres in a LAMMPS data file.

Prints the packing fraction, the radial distribution g(r) near contact and at the split second
peak (r = sqrt(3) and 2 diameters, the signature of random close packing), and Steinhardt
bond order with neighbours closer than 1.4 diameters: the global Q6 (0.575 for FCC, ~0 for an
amorphous packing), the mean local q6, and the fraction of crystal-like spheres (ten Wolde,
Ruiz-Montero and Frenkel 1996: at least 7 neighbours whose normalised q6 vectors have a dot
product above 0.7). Wall axes are analysed without images (spheres by a wall simply have fewer
neighbours). Usage, from the repository root:
    python3 -m compare.packing_structure FILE [--boundary p,p,w]
    python3 -m compare.packing_structure --fcc    (an FCC reference)
"""
import math

import numpy as np
from scipy.spatial import cKDTree
from scipy.special import lpmv

from compare import harness
from compare.lammps_files import read_data

L_ORDER = 6


def read_packing(path):
    """Diameters, positions from the box's low corner, and box lengths of a data file."""
    d = read_data(path)
    return d.diameter, d.pos - d.box[:, 0], d.lengths


def fcc(cells, phi):
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.array([[i, j, k] for i in range(cells) for j in range(cells) for k in range(cells)], float)
    x = (g[:, None, :] + basis[None, :, :]).reshape(-1, 3)
    a = (4 * math.pi / 6 / phi) ** (1 / 3)  # unit diameters
    return np.ones(len(x)), x * a, np.full(3, cells * a)


def ylm(l, bonds):
    """Complex spherical harmonics Y_lm, m = -l..l, of the bond directions (rows)."""
    r = np.linalg.norm(bonds, axis=1)
    ct = np.clip(bonds[:, 2] / r, -1, 1)
    ph = np.arctan2(bonds[:, 1], bonds[:, 0])
    out = np.empty((len(bonds), 2 * l + 1), complex)
    for m in range(0, l + 1):
        k = math.sqrt((2 * l + 1) / (4 * math.pi) * math.factorial(l - m) / math.factorial(l + m))
        y = k * lpmv(m, l, ct) * np.exp(1j * m * ph)
        out[:, l + m] = y
        out[:, l - m] = (-1) ** m * np.conj(y)
    return out


def analyse(diam, x, box, periodic=(True, True, True)):
    n, sigma = len(x), float(np.mean(diam))
    phi = float(np.sum(math.pi / 6 * diam ** 3) / np.prod(box))
    # A wall axis becomes a periodic one three times as long, so no pair meets through it.
    x, box = x.copy(), box.copy()
    for d in range(3):
        if not periodic[d]:
            x[:, d] += box[d]
            box[d] *= 3
    tree = cKDTree(np.mod(x, box), boxsize=box)
    pairs = tree.query_pairs(2.2 * sigma, output_type="ndarray")
    dr = x[pairs[:, 1]] - x[pairs[:, 0]]
    dr -= box * np.round(dr / box)
    r = np.linalg.norm(dr, axis=1) / sigma
    rho = 6 * phi / math.pi
    edges = np.linspace(0.9, 2.2, 131)
    hist, _ = np.histogram(r, edges)
    shell = 4 / 3 * math.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    g = hist / (0.5 * n * rho * shell)
    centre = 0.5 * (edges[1:] + edges[:-1])
    near = r < 1.4
    bi, bj, bv = pairs[near, 0], pairs[near, 1], dr[near]
    y = ylm(L_ORDER, bv)
    q = np.zeros((n, 2 * L_ORDER + 1), complex)
    cnt = np.bincount(bi, minlength=n) + np.bincount(bj, minlength=n)
    np.add.at(q, bi, y)
    np.add.at(q, bj, y * (-1) ** L_ORDER)  # Y_lm(-b) = (-1)^l Y_lm(b)
    q_global = np.sum(q, axis=0) / max(1, cnt.sum())
    q6_global = math.sqrt(4 * math.pi / (2 * L_ORDER + 1) * np.sum(np.abs(q_global) ** 2))
    q = q / np.maximum(cnt, 1)[:, None]
    norm = np.linalg.norm(q, axis=1)
    q6_local = np.sqrt(4 * math.pi / (2 * L_ORDER + 1)) * norm
    qn = q / np.maximum(norm, 1e-300)[:, None]
    dot = np.real(np.sum(qn[bi] * np.conj(qn[bj]), axis=1))
    links = np.bincount(bi[dot > 0.7], minlength=n) + np.bincount(bj[dot > 0.7], minlength=n)
    peak = int(np.argmax(g))
    at = lambda r0: float(g[np.argmin(np.abs(centre - r0))])
    return {
        "N": n, "phi": phi, "g_peak_r": float(centre[peak]), "g_peak": float(g[peak]),
        "g(sqrt3)": at(math.sqrt(3)), "g(2)": at(2.0), "g(1.85)": at(1.85),
        "neighbours<1.4": float(cnt.mean()), "Q6": q6_global, "mean q6": float(q6_local.mean()),
        "crystal-like": float(np.mean(links >= 7)),
    }


def parse_boundary(text):
    letters = text.split(",")
    return tuple(c == "p" for c in (letters * 3 if len(letters) == 1 else letters))


def main(argv=None):
    ap = harness.parser(__doc__, out=False)
    ap.add_argument("file", nargs="?", help="a LAMMPS data file of the packing")
    ap.add_argument("--boundary", default="p", help="p or w per axis, e.g. p,p,w (default: periodic)")
    ap.add_argument("--fcc", action="store_true", help="analyse an FCC reference instead of a file")
    a = ap.parse_args(argv)
    if not a.fcc and not a.file:
        raise harness.InputError("give a data file or --fcc")
    diam, x, box = fcc(10, 0.62) if a.fcc else read_packing(a.file)
    for k, v in analyse(diam, x, box, parse_boundary(a.boundary)).items():
        print(f"{k:>15} {v:.4g}" if isinstance(v, float) else f"{k:>15} {v}")
    return 0


if __name__ == "__main__":
    harness.main(main)
