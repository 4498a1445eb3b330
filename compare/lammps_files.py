"""LAMMPS files: atom_style sphere data files, text dumps, and the thermo and loop-time lines of a
log. The one reader (and writer) of these formats for every Python program of the project.

Data files, as `hardsphere run --write-data` and LAMMPS's `write_data` write them:

    data = read_data(path)            # SphereData, rows sorted by atom id
    data.pos, data.vel, data.radius, data.mass, data.box, data.lengths, data.unwrapped()
    write_data(path, data)            # every number as repr(): a double round-trips
    write_data(path, spheres(pos, vel, box=((0, 10),) * 3, diameter=1.0))

The header's counts ("N atoms", "N atom types", "N bonds", ... in `counts`), the box ("lo hi xlo
xhi", ...) and its tilt ("xy xz yz", None without one); the sections Masses, Atoms (id type diameter
density x y z, with or without the image flags ix iy iz) and Velocities (id vx vy vz, with or
without the angular velocity wx wy wz of LAMMPS's sphere style); other sections (Pair Coeffs, ...)
are skipped. A file with another atom style ("Atoms # atomic") or too few rows is refused
(ValueError).

Text dumps (dump atom / custom / write_dump of LAMMPS, LIGGGHTS, hardsphere --dump) with any
column set, orthogonal or triclinic box:

    for frame in read_dump(path):     # DumpFrame, one at a time, rows sorted by id
        frame.timestep, frame.box, frame.tilt, frame.bounds, frame.names, frame["xu"]
    write_dump(path, frames)

Logs: `thermo_blocks(text)` (one list of rows per thermo block, a row a dict of floats) and
`loop_times(text)` ([(seconds, procs, steps)], one per 'Loop time of' line).

Importing this module has no side effects.
"""
import math
import re
from dataclasses import dataclass, field

import numpy as np

AXES = "xyz"
# pi/6 d^3 is a sphere's volume; a unit sphere of unit mass has density 6/pi.
UNIT_DENSITY = 6.0 / math.pi


# --- data files ------------------------------------------------------------------------------

@dataclass
class SphereData:
    """A data file of atom_style sphere. Arrays have one row per atom, sorted by id.

    box: (3, 2) lo, hi per axis; tilt: (xy, xz, yz) or None; counts: the header's counts by name
    ('atoms', 'atom types', 'bonds', ...); masses: {type: mass} from a Masses section (LAMMPS
    writes one; sphere atoms take their mass from diameter and density); image: (N, 3) ints or
    None (no image flags in the file); omega: (N, 3) angular velocities or None (Velocities rows
    without wx wy wz, or no Velocities section); vel is zero without a Velocities section."""
    box: np.ndarray
    ids: np.ndarray
    types: np.ndarray
    diameter: np.ndarray
    density: np.ndarray
    pos: np.ndarray
    vel: np.ndarray
    image: np.ndarray = None
    omega: np.ndarray = None
    tilt: np.ndarray = None
    title: str = "hardsphere state"
    ntypes: int = None
    counts: dict = field(default_factory=dict)
    masses: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.ntypes is None:
            self.ntypes = int(self.types.max()) if len(self.types) else 1

    def __len__(self):
        return len(self.ids)

    @property
    def radius(self):
        return 0.5 * self.diameter

    @property
    def mass(self):
        """density x volume; a point particle (diameter 0) has its mass in the density column."""
        volume = math.pi / 6.0 * self.diameter ** 3
        return np.where(self.diameter > 0, self.density * volume, self.density)

    @property
    def lengths(self):
        return self.box[:, 1] - self.box[:, 0]

    @property
    def volume(self):
        return float(np.prod(self.lengths))

    def unwrapped(self):
        """Positions plus image flags times the box lengths (the positions without image flags)."""
        if self.image is None:
            return self.pos.copy()
        shift = self.image * self.lengths
        if self.tilt is not None:  # a y image moves x by xy, a z image x by xz and y by yz
            xy, xz, yz = self.tilt
            shift[:, 0] += self.image[:, 1] * xy + self.image[:, 2] * xz
            shift[:, 1] += self.image[:, 2] * yz
        return self.pos + shift


def spheres(pos, vel=None, *, box, diameter=1.0, density=None, mass=None, types=1, image=None, omega=None,
            tilt=None, title="hardsphere state"):
    """SphereData from arrays, ids 1..N. diameter, types and density (or mass) broadcast; without
    either the spheres have unit mass."""
    pos = np.asarray(pos, dtype=float).reshape(-1, 3)
    n = len(pos)
    diameter = np.broadcast_to(np.asarray(diameter, dtype=float), (n,)).copy()
    if density is None:
        m = np.broadcast_to(np.asarray(1.0 if mass is None else mass, dtype=float), (n,))
        volume = math.pi / 6.0 * diameter ** 3
        density = np.where(diameter > 0, m / np.where(diameter > 0, volume, 1.0), m)
    elif mass is not None:
        raise ValueError("give density or mass, not both")
    return SphereData(box=np.asarray(box, dtype=float).reshape(3, 2), ids=np.arange(1, n + 1),
                      types=np.broadcast_to(np.asarray(types, dtype=int), (n,)).copy(), diameter=diameter,
                      density=np.broadcast_to(np.asarray(density, dtype=float), (n,)).copy(), pos=pos,
                      vel=np.zeros((n, 3)) if vel is None else np.asarray(vel, dtype=float).reshape(n, 3),
                      image=None if image is None else np.asarray(image, dtype=np.int64).reshape(n, 3),
                      omega=None if omega is None else np.broadcast_to(np.asarray(omega, dtype=float), (n, 3)).copy(),
                      tilt=None if tilt is None else np.asarray(tilt, dtype=float), title=title)


def spheres_from_rows(rows, *, box, title="hardsphere state"):
    """SphereData from rows (x, y, z, vx, vy, vz[, diameter[, density]]), ids 1..N: diameter 1 and
    density 6/pi (the mass of a unit sphere: 1) where a row leaves them out."""
    rows = [tuple(map(float, r)) for r in rows]
    diameter = np.array([r[6] if len(r) > 6 else 1.0 for r in rows])
    density = np.array([r[7] if len(r) > 7 else UNIT_DENSITY for r in rows])
    return spheres([r[:3] for r in rows], [r[3:6] for r in rows], box=box, diameter=diameter, density=density,
                   title=title)


def _is_number(word):
    try:
        float(word)
        return True
    except ValueError:
        return False


def _section_rows(path, rows, name, width, count):
    """(N, width) array of a section's rows; every row has one of the widths in `width`."""
    if len(rows) != count:
        raise ValueError(f"{path}: {name} has {len(rows)} rows, the header says {count} atoms")
    widths = {len(r) for r in rows}
    if len(widths) > 1 or (rows and widths.pop() not in width):
        raise ValueError(f"{path}: {name} rows must all have {' or '.join(map(str, width))} columns")
    return rows


def read_data(path):
    """The SphereData of a data file (atom_style sphere)."""
    with open(path) as f:
        title = f.readline().rstrip("\n")
        lines = f.read().splitlines()
    counts, box, tilt, sections, current, style = {}, np.zeros((3, 2)), None, {}, None, {}
    for raw in lines:
        line, _, comment = raw.partition("#")
        w = line.split()
        if not w:
            continue
        if not _is_number(w[0]):  # a section name
            current = " ".join(w)
            if current in sections:
                raise ValueError(f"{path}: a second {current} section")
            sections[current] = []
            style[current] = comment.strip()
            continue
        if current is not None:
            sections[current].append(w)
        elif w[-2:] in (["xlo", "xhi"], ["ylo", "yhi"], ["zlo", "zhi"]):
            box[AXES.index(w[-2][0])] = float(w[0]), float(w[1])
        elif w[-3:] == ["xy", "xz", "yz"]:
            tilt = np.array([float(v) for v in w[:3]])
        else:  # "N atoms", "N atom types", "N bonds", "N extra bond per atom", ...
            counts[" ".join(w[1:])] = int(w[0])
    if "Atoms" not in sections:
        raise ValueError(f"{path}: no Atoms section")
    if style["Atoms"] and style["Atoms"].split()[0] != "sphere":
        raise ValueError(f"{path}: atom style {style['Atoms'].split()[0]!r}, not sphere")
    n = counts.get("atoms", 0)
    atoms = sorted(_section_rows(path, sections["Atoms"], "Atoms", (7, 10), n), key=lambda r: int(r[0]))
    ids = np.array([int(r[0]) for r in atoms], dtype=np.int64)
    if len(set(ids.tolist())) != n:
        raise ValueError(f"{path}: an atom id appears twice in Atoms")
    a = np.array([[float(v) for v in r[2:7]] for r in atoms]).reshape(n, 5)
    image = np.array([[int(v) for v in r[7:10]] for r in atoms], dtype=np.int64) if atoms and len(atoms[0]) == 10 \
        else None
    vel, omega = np.zeros((n, 3)), None
    if "Velocities" in sections:
        rows = {int(r[0]): r for r in _section_rows(path, sections["Velocities"], "Velocities", (4, 7), n)}
        if set(rows) != set(ids.tolist()):
            raise ValueError(f"{path}: the Velocities ids are not the Atoms ids")
        v = np.array([[float(x) for x in rows[i][1:]] for i in ids.tolist()]).reshape(n, -1)
        vel = v[:, :3].copy()
        omega = v[:, 3:6].copy() if v.shape[1] == 6 else None
    masses = {int(r[0]): float(r[1]) for r in sections.get("Masses", [])}
    return SphereData(box=box, ids=ids, types=np.array([int(r[1]) for r in atoms], dtype=np.int64),
                      diameter=a[:, 0].copy(), density=a[:, 1].copy(), pos=a[:, 2:5].copy(), vel=vel, image=image,
                      omega=omega, tilt=tilt, title=title, ntypes=counts.get("atom types", 1), counts=counts,
                      masses=masses)


def write_data(path, data):
    """Writes `data` as hardsphere and LAMMPS read it (Atoms # sphere; image flags and wx wy wz
    when data has them). Returns str(path)."""
    ntypes = max(data.ntypes, int(data.types.max()) if len(data) else 1)
    lines = [data.title, "", f"{len(data)} atoms", f"{ntypes} atom types", ""]
    lines += [f"{lo!r} {hi!r} {a}lo {a}hi" for (lo, hi), a in zip(data.box.tolist(), AXES)]
    if data.tilt is not None:
        lines.append(" ".join(repr(float(t)) for t in data.tilt) + " xy xz yz")
    if data.masses:
        lines += ["", "Masses", ""] + [f"{t} {m!r}" for t, m in sorted(data.masses.items())]
    lines += ["", "Atoms # sphere", ""]
    for k in range(len(data)):
        row = [str(int(data.ids[k])), str(int(data.types[k]))] + \
              [repr(float(v)) for v in (data.diameter[k], data.density[k], *data.pos[k])]
        if data.image is not None:
            row += [str(int(i)) for i in data.image[k]]
        lines.append(" ".join(row))
    lines += ["", "Velocities", ""]
    for k in range(len(data)):
        row = [str(int(data.ids[k]))] + [repr(float(v)) for v in data.vel[k]]
        if data.omega is not None:
            row += [repr(float(v)) for v in data.omega[k]]
        lines.append(" ".join(row))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return str(path)


# --- dumps -----------------------------------------------------------------------------------

# Columns read as integers (LAMMPS writes them as integers).
INT_COLUMNS = {"id", "type", "mol", "ix", "iy", "iz", "proc", "procp1"}


@dataclass
class DumpFrame:
    """One snapshot of a text dump. box: (3, 2) lo, hi of the (possibly tilted) box; tilt: (xy,
    xz, yz) or None; bounds: the boundary words ('pp pp ff'); time and units when the dump has
    them (dump_modify time / units yes); columns: one array per dumped column under its dump name
    ('id', 'xu', 'c_sa[1]', ...), rows sorted by id when the dump has ids, in the file's order
    otherwise; frame[name], `name in frame` and iterating over the frame (the names) read them."""
    timestep: int
    box: np.ndarray
    bounds: str
    columns: dict
    tilt: np.ndarray = None
    time: float = None
    units: str = None

    def __getitem__(self, name):
        return self.columns[name]

    def __contains__(self, name):
        return name in self.columns

    def __iter__(self):
        return iter(self.columns)

    @property
    def names(self):
        return list(self.columns)

    @property
    def natoms(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    @property
    def box_lo(self):
        return self.box[:, 0]

    @property
    def box_hi(self):
        return self.box[:, 1]

    @property
    def unwrapped(self):
        """True when positions() are unwrapped (xu yu zu, or x y z with image flags)."""
        return "xu" in self.columns or "ix" in self.columns

    def positions(self):
        """(N, 3) positions: xu yu zu, else x y z plus the image flags times the box lengths (an
        orthogonal box), else x y z."""
        c = self.columns
        if "xu" in c:
            return np.column_stack([c["xu"], c["yu"], c["zu"]])
        x = np.column_stack([c["x"], c["y"], c["z"]])
        if "ix" in c:
            if self.tilt is not None:
                raise ValueError("image flags of a triclinic dump: dump xu yu zu instead")
            x = x + np.column_stack([c["ix"], c["iy"], c["iz"]]) * (self.box_hi - self.box_lo)
        return x

    def table(self, names=None):
        """(N, len(names)) float array of the named columns (all by default), in that order."""
        names = self.names if names is None else names
        return np.column_stack([self.columns[c].astype(float) for c in names]) if names else np.zeros((self.natoms, 0))


def _expect(path, line, item):
    if not line.startswith(item):
        raise ValueError(f"{path}: expected {item!r}, got {line.strip()!r}")


def read_dump(path, sort=True):
    """Frames of a text dump, one at a time (a generator of DumpFrame)."""
    with open(path) as f:
        while True:
            line = f.readline()
            if not line:
                return
            if not line.strip():
                continue
            # A frame's items up to NUMBER OF ATOMS: UNITS and TIME (dump_modify units / time yes,
            # before TIMESTEP), TIMESTEP, LIGGGHTS's LABEL ...
            timestep, time, units, head = None, None, None, line
            while not head.startswith("ITEM: NUMBER OF ATOMS"):
                if not head.startswith("ITEM:"):
                    raise ValueError(f"{path}: expected 'ITEM: NUMBER OF ATOMS', got {head.strip()!r}")
                value = f.readline().strip()
                if head.startswith("ITEM: TIMESTEP"):
                    timestep = int(value.split()[0])
                elif head.startswith("ITEM: TIME"):
                    time = float(value)
                elif head.startswith("ITEM: UNITS"):
                    units = value
                head = f.readline()
            if timestep is None:
                raise ValueError(f"{path}: a frame without 'ITEM: TIMESTEP'")
            n = int(f.readline())
            head = f.readline()
            _expect(path, head, "ITEM: BOX BOUNDS")
            words = head.split()[3:]
            if words and words[0] == "abc":
                raise ValueError(f"{path}: general triclinic boxes are not supported")
            triclinic = words[:3] == ["xy", "xz", "yz"]
            rows = np.array([[float(v) for v in f.readline().split()] for _ in range(3)])
            tilt = None
            if triclinic:  # the lines hold the bounding box and the tilt factors
                tilt = rows[:, 2].copy()
                xy, xz, yz = tilt
                rows[0, 0] -= min(0.0, xy, xz, xy + xz)
                rows[0, 1] -= max(0.0, xy, xz, xy + xz)
                rows[1, 0] -= min(0.0, yz)
                rows[1, 1] -= max(0.0, yz)
                words = words[3:]
            head = f.readline()
            _expect(path, head, "ITEM: ATOMS")
            names = head.split()[2:]
            text = "".join(f.readline() for _ in range(n))
            values = np.array(text.split(), dtype=float)
            if values.size != n * len(names):
                raise ValueError(f"{path}: truncated frame at timestep {timestep}")
            values = values.reshape(n, len(names))
            if sort and "id" in names:
                values = values[np.argsort(values[:, names.index("id")], kind="stable")]
            columns = {c: values[:, k].astype(np.int64) if c in INT_COLUMNS else values[:, k]
                       for k, c in enumerate(names)}
            yield DumpFrame(timestep=timestep, box=rows[:, :2].copy(), bounds=" ".join(words), columns=columns,
                            tilt=tilt, time=time, units=units)


def read_dump_frames(path, sort=True):
    """Every frame of a text dump as a list."""
    return list(read_dump(path, sort))


def write_dump(path, frames):
    """Writes DumpFrames as LAMMPS writes a text dump (floats as repr(): they round-trip)."""
    out = []
    for fr in frames:
        if fr.units is not None:
            out += ["ITEM: UNITS", fr.units]
        if fr.time is not None:
            out += ["ITEM: TIME", repr(float(fr.time))]
        out += ["ITEM: TIMESTEP", str(fr.timestep)]
        out += ["ITEM: NUMBER OF ATOMS", str(fr.natoms)]
        if fr.tilt is None:
            out.append(f"ITEM: BOX BOUNDS {fr.bounds}".rstrip())
            out += [f"{lo!r} {hi!r}" for lo, hi in fr.box.tolist()]
        else:
            xy, xz, yz = (float(t) for t in fr.tilt)
            (xlo, xhi), (ylo, yhi), (zlo, zhi) = fr.box.tolist()
            bound = [(xlo + min(0.0, xy, xz, xy + xz), xhi + max(0.0, xy, xz, xy + xz), xy),
                     (ylo + min(0.0, yz), yhi + max(0.0, yz), xz), (zlo, zhi, yz)]
            out.append(f"ITEM: BOX BOUNDS xy xz yz {fr.bounds}".rstrip())
            out += [f"{lo!r} {hi!r} {t!r}" for lo, hi, t in bound]
        out.append("ITEM: ATOMS " + " ".join(fr.names))
        cols = [fr.columns[c] for c in fr.names]
        for k in range(fr.natoms):
            out.append(" ".join(str(int(c[k])) if c.dtype.kind in "iu" else repr(float(c[k])) for c in cols))
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return str(path)


# --- logs ------------------------------------------------------------------------------------

def thermo_blocks(text):
    """Every thermo block of a LAMMPS log or screen output (one per run, rerun or minimize): a list
    of rows, each a dict of floats keyed by the thermo keywords ('Step', 'KinEng', 'f_hs[1]', ...).
    A block ends at its 'Loop time' line or at the first line that is not a row of it."""
    blocks, head = [], None
    for line in text.splitlines():
        s = line.split()
        if s and s[0] == "Step":
            head = s
            blocks.append([])
        elif head and len(s) == len(head):
            try:
                blocks[-1].append(dict(zip(head, map(float, s))))
            except ValueError:
                head = None
        elif head and s and s[0] == "Loop":
            head = None
    return blocks


def thermo_rows(text):
    """The rows of the last thermo block ([] without one)."""
    blocks = thermo_blocks(text)
    return blocks[-1] if blocks else []


_LOOP = re.compile(r"Loop time of\s+([-+0-9.eE]+)\s+on\s+(\d+)\s+procs\s+for\s+(\d+)\s+steps")


def loop_times(text):
    """[(seconds, procs, steps), ...], one per 'Loop time of X on P procs for S steps' line (one per
    run command; LIGGGHTS appends ', finish time ...')."""
    return [(float(s), int(p), int(n)) for s, p, n in _LOOP.findall(text)]
