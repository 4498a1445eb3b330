"""Initial states for the cross-validation: LAMMPS data files (atom_style sphere), equilibrated by
the event engine, cached by name.

Monodisperse: `hardsphere run` makes the state. Binary 50/50 mixture of diameters 1 and 1.4 (equal
mass density, so masses 1 and 1.4^3): random points pushed apart by minimising a soft repulsion
in Debian's LAMMPS (contact distance 1.001 sigma_ij, so no hard-sphere overlap remains), then
Maxwell-Boltzmann velocities at T = 1.
"""
import functools
import math
import subprocess
from pathlib import Path

from compare import soft_spheres
from compare.lammps_files import UNIT_DENSITY, read_data

BIG = 1.4

PUSH_OFF = """units lj
atom_style sphere
boundary p p p
region box block 0 {L!r} 0 {L!r} 0 {L!r}
create_box 2 box
create_atoms 1 random {n1} {seed} NULL
create_atoms 2 random {n2} {seed2} NULL
set type 1 diameter 1.0
set type 2 diameter {big!r}
set group all density {rho!r}
pair_style soft {cut2!r}
pair_coeff 1 1 50.0 {cut11!r}
pair_coeff 1 2 50.0 {cut12!r}
pair_coeff 2 2 50.0 {cut2!r}
min_style fire
minimize 0.0 1.0e-12 20000 200000
min_style cg
minimize 0.0 1.0e-14 20000 200000
velocity all create 1.0 {seed3} dist gaussian mom yes
write_data {out} nocoeff
"""


class StateError(RuntimeError):
    pass


def species(composition):
    """(number fraction, diameter, mass) per species."""
    if composition == "mono":
        return [(1.0, 1.0, 1.0)]
    return [(0.5, 1.0, 1.0), (0.5, BIG, BIG**3)]


def name(n, phi, composition):
    return f"{composition}_n{n}_phi{phi}"


def max_overlap(path):
    s = read_state(path)
    delta = soft_spheres.contacts(s.pos, s.radius, s.box[:, 0], s.box[:, 1])[4]
    return float(delta.max()) if len(delta) else 0.0


def make_state(hs, lmp, out_dir, n, phi, composition, equilibrate_time, seed=1, log=print):
    """The equilibrated state's data file (cached in out_dir)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    final = out_dir / f"{name(n, phi, composition)}.data"
    if final.exists():
        return final
    raw = out_dir / f"{name(n, phi, composition)}.raw.data"
    if composition == "mono":
        _check([hs, "run", "--n", n, "--phi", phi, "--seed", seed, "--steps", 0, "--write-data", raw], out_dir)
    else:
        n1 = n // 2
        volume = (n1 * math.pi / 6 + (n - n1) * math.pi / 6 * BIG**3) / phi
        script = out_dir / f"{name(n, phi, composition)}.in"
        script.write_text(PUSH_OFF.format(L=volume ** (1 / 3), n1=n1, n2=n - n1, seed=seed * 7 + 11,
                                          seed2=seed * 7 + 13, seed3=seed * 7 + 17, big=BIG, rho=UNIT_DENSITY,
                                          cut11=1.001, cut12=1.001 * (1 + BIG) / 2, cut2=1.001 * BIG, out=raw.name))
        _check([lmp, "-in", script.name, "-log", "none", "-screen", "none"], out_dir)
        script.unlink()
        overlap = max_overlap(raw)
        if overlap > 0:
            raise StateError(f"the soft push-off left an overlap of {overlap:.3g} in {raw}")
    log(f"state {final.name}: equilibrating for time {equilibrate_time} with the event engine")
    _check([hs, "run", "--engine", "event", "--read-data", raw, "--time", equilibrate_time, "--blocks", 1,
            "--write-data", final], out_dir)
    raw.unlink()
    return final


def _check(cmd, cwd):
    p = subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True)
    if p.returncode != 0:
        raise StateError(f"{' '.join(map(str, cmd))} failed ({p.returncode}): {(p.stdout + p.stderr)[-400:]}")


@functools.lru_cache(maxsize=4)
def read_state(path):
    """The state's data file, read once per path (every run of a state needs its masses and box)."""
    return read_data(path)


def box(state_path):
    """(lo, hi) of the state's box."""
    b = read_state(state_path).box
    return b[:, 0].copy(), b[:, 1].copy()


def masses(state_path):
    """Masses sorted by id (dumps are sorted by id too)."""
    s = read_state(state_path)
    return s.mass  # sorted by id


def type_count(state_path):
    return len(set(read_state(state_path).types.tolist()))
