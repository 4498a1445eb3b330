#!/usr/bin/python3
"""Writes a LAMMPS data file (atom_style sphere) of a hard-sphere gas with a few big spheres.

Big spheres come first (ids 1..K, type 2), at random non-overlapping places; small spheres (type 1)
are added at random places, largest first, each clear of those before (random sequential addition,
fine up to phi ~0.3). Velocities are Maxwell-Boltzmann at T with the
total momentum removed. The box is cubic and periodic; phi counts every sphere.

  python3 -m compare.big_sphere_scene --n 20000 --phi 0.2 --big 1 --big-diameter 10 --big-mass 1000 --out big.data
  python3 -m compare.big_sphere_scene --n 20000 --phi 0.2 --sizes uniform:0.5,1.5 --out poly.data
  python3 -m compare.big_sphere_scene --n 20000 --phi 0.2 --sizes lognormal:0.25 --out lognormal.data
"""
import math

import numpy as np

from compare import harness
from compare.lammps_files import spheres, write_data


def small_diameters(spec, n, rng):
    """Diameters of the small spheres: 'mono' (1), 'uniform:a,b' or 'lognormal:s' (median 1)."""
    kind, _, arg = spec.partition(":")
    if kind == "mono":
        return np.ones(n)
    if kind == "uniform":
        a, b = (float(x) for x in arg.split(","))
        if not 0 < a <= b:
            raise ValueError(f"uniform sizes need 0 < a <= b, got {arg}")
        return rng.uniform(a, b, n)
    if kind == "lognormal":
        s = float(arg)
        if not s > 0:
            raise ValueError(f"lognormal sizes need s > 0, got {arg}")
        return rng.lognormal(0.0, s, n)
    raise ValueError(f"unknown size distribution {spec!r} (mono, uniform:a,b, lognormal:s)")


def min_image(d, length):
    return d - length * np.round(d / length)


def place_small(diameters, big_pos, big_diameter, length, rng, attempts=100000):
    """Random sequential addition, largest first, each sphere clear of the big ones and of those
    placed before; a cell grid as wide as the largest small diameter keeps each test local."""
    n = len(diameters)
    pos = np.zeros((n, 3))
    if n == 0:
        return pos
    dmax = float(diameters.max())
    side = max(int(length // dmax), 1)
    width = length / side
    cells = {}
    for i in np.argsort(-diameters, kind="stable"):
        d = float(diameters[i])
        for _attempt in range(attempts):
            p = rng.uniform(0, length, 3)
            if len(big_pos) and np.any(
                np.linalg.norm(min_image(big_pos - p, length), axis=1) < 0.5 * (big_diameter + d)
            ):
                continue
            c = (p // width).astype(int) % side
            clear = True
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for dz in (-1, 0, 1):
                        for j in cells.get(((c[0] + dx) % side, (c[1] + dy) % side, (c[2] + dz) % side), ()):
                            if np.linalg.norm(min_image(pos[j] - p, length)) < 0.5 * (d + diameters[j]):
                                clear = False
                                break
                        if not clear:
                            break
                    if not clear:
                        break
                if not clear:
                    break
            if clear:
                pos[i] = p
                cells.setdefault(tuple(int(k) for k in c), []).append(i)
                break
        else:
            raise ValueError(f"no room for sphere {i + 1} of diameter {d:.4g} after {attempts} attempts (phi too high)")
    return pos


def make_scene(n, phi, big=0, big_diameter=10.0, big_mass=None, sizes="mono", temperature=1.0, seed=1):
    """Returns dict(box=L, diameter, mass, type, pos (N,3), vel (N,3)); big spheres first."""
    rng = np.random.default_rng(seed)
    d_small = small_diameters(sizes, n, rng)
    d_big = np.full(big, float(big_diameter))
    volume = math.pi / 6 * (np.sum(d_small**3) + np.sum(d_big**3))
    length = (volume / phi) ** (1 / 3)
    # Big spheres: random places, each clear of the others (rejection; they are few).
    big_pos = []
    for _ in range(big):
        for _attempt in range(10000):
            p = rng.uniform(0, length, 3)
            if all(np.linalg.norm(min_image(p - q, length)) > big_diameter for q in big_pos):
                big_pos.append(p)
                break
        else:
            raise ValueError(f"no room for {big} big spheres of diameter {big_diameter} in a box of {length:.4g}")
    big_pos = np.array(big_pos).reshape(-1, 3)
    small_pos = place_small(d_small, big_pos, big_diameter, length, rng)
    diameter = np.concatenate([d_big, d_small])
    mass = diameter**3  # unit density: a sphere of diameter 1 has mass 1
    if big and big_mass is not None:
        mass[:big] = big_mass
    vel = rng.normal(size=(big + n, 3)) * np.sqrt(temperature / mass)[:, None]
    vel -= (mass[:, None] * vel).sum(axis=0) / mass.sum()
    pos = np.concatenate([big_pos, small_pos])
    kind = np.concatenate([np.full(big, 2), np.ones(n, int)])
    return dict(box=length, diameter=diameter, mass=mass, type=kind, pos=pos, vel=vel)


def write_scene(path, scene, title="hardsphere gas with big spheres"):
    """LAMMPS data file; density = mass / volume so LAMMPS and hardsphere read the same masses. The
    angular velocities are zero (hard spheres are smooth)."""
    length = scene["box"]
    write_data(path, spheres(scene["pos"], scene["vel"], box=((0.0, length),) * 3, diameter=scene["diameter"],
                             mass=scene["mass"], types=scene["type"], omega=0.0, title=title))


def main(argv=None):
    ap = harness.parser(__doc__, out=False)
    ap.add_argument("--n", type=int, required=True, help="number of small spheres")
    ap.add_argument("--phi", type=float, required=True, help="packing fraction of all spheres")
    ap.add_argument("--big", type=int, default=0, help="number of big spheres (0)")
    ap.add_argument("--big-diameter", type=float, default=10.0)
    ap.add_argument("--big-mass", type=float, default=None, help="mass of a big sphere (default: diameter^3)")
    ap.add_argument("--sizes", default="mono", help="small diameters: mono, uniform:a,b or lognormal:s (mono)")
    ap.add_argument("--temperature", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", required=True, help="the data file to write")
    a = ap.parse_args(argv)
    try:
        scene = make_scene(a.n, a.phi, a.big, a.big_diameter, a.big_mass, a.sizes, a.temperature, a.seed)
    except ValueError as e:
        raise harness.InputError(str(e)) from None
    write_scene(a.out, scene)
    print(f"{a.out}: {a.big} big + {a.n} small spheres, box {scene['box']:.6g}")
    return 0


if __name__ == "__main__":
    harness.main(main)
