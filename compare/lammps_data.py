"""Read LAMMPS data files (atom_style sphere) as written by `hardsphere run --write-data`."""
import math

import numpy as np


def read_sphere_data(path):
    """Returns dict with ids, types, radius, mass, pos (N,3), vel (N,3), box (3,2)."""
    with open(path) as f:
        lines = [ln.split("#")[0].strip() for ln in f][1:]
    natoms, box = None, np.zeros((3, 2))
    atoms, vels = {}, {}
    i = 0
    while i < len(lines):
        w = lines[i].split()
        i += 1
        if not w:
            continue
        if len(w) == 2 and w[1] == "atoms":
            natoms = int(w[0])
        elif len(w) == 4 and w[2] in ("xlo", "ylo", "zlo"):
            box["xyz".index(w[2][0])] = float(w[0]), float(w[1])
        elif w[0] in ("Atoms", "Velocities"):
            target = atoms if w[0] == "Atoms" else vels
            read = 0
            while read < natoms:
                v = lines[i].split()
                i += 1
                if v:
                    target[int(v[0])] = [float(x) for x in v[1:]]
                    read += 1
    ids = np.array(sorted(atoms))
    a = np.array([atoms[k] for k in ids])
    radius = 0.5 * a[:, 1]
    mass = a[:, 2] * (4.0 * math.pi / 3.0 * radius**3)
    vel = np.array([vels.get(k, [0, 0, 0])[:3] for k in ids])
    return dict(ids=ids, types=a[:, 0].astype(int), radius=radius, mass=mass, pos=a[:, 3:6], vel=vel, box=box)


def write_sphere_data(path, atoms, box=((0, 10),) * 3, title="hardsphere state"):
    """Writes atom_style sphere rows (x, y, z, vx, vy, vz[, diameter[, density]]) with ids from 1.

    Diameter 1 and density 6/pi (unit mass) unless given; values as repr(), so every double round-trips.
    """
    unit_density = 6 / math.pi
    lines = [title, "", f"{len(atoms)} atoms", "1 atom types", ""]
    lines += [f"{lo!r} {hi!r} {a}lo {a}hi" for (lo, hi), a in zip(box, "xyz")]
    lines += ["", "Atoms # sphere", ""]
    for i, a in enumerate(atoms, 1):
        d = a[6] if len(a) > 6 else 1.0
        rho = a[7] if len(a) > 7 else unit_density
        lines.append(f"{i} 1 {d!r} {rho!r} {a[0]!r} {a[1]!r} {a[2]!r}")
    lines += ["", "Velocities", ""] + [f"{i} {a[3]!r} {a[4]!r} {a[5]!r}" for i, a in enumerate(atoms, 1)]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return str(path)
