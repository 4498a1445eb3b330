"""Soft elastic spheres as the LAMMPS granular styles and LIGGGHTS model them, for comparison with
hard spheres: pair energies and forces, the Barker-Henderson (BH) shift of the contact distance,
the total elastic energy and pair virial of a periodic configuration, head-on contact times, and
the reader of the block-averaged virial file that the reference inputs write
(reference_inputs/lammps/in.granular_*, reference_inputs/liggghts/in.granular_hertz; their dumps
and logs are read by compare.lammps_files).

Importing this module has no side effects. Units are those of the inputs (reduced, k_B = 1).

Force laws for the overlap delta = R_i + R_j - r > 0 of a pair with reduced radius
Reff = R_i R_j / (R_i + R_j) (verified in the sources and in tests/compare/test_soft_spheres.py):

  model           force F(delta)                         energy u(delta)
  'hooke'         kn delta                               kn delta^2 / 2
                  (LAMMPS gran/hooke, src/GRANULAR/pair_gran_hooke.cpp)
  'hertz_lammps'  kn sqrt(Reff delta) delta              (2/5) kn sqrt(Reff) delta^(5/2)
                  (LAMMPS gran/hertz/history: the Hookean term times sqrt(delta Reff),
                  src/GRANULAR/pair_gran_hertz_history.cpp, 'polyhertz'; kn in force/area)
  'hertz_liggghts' 4/3 Y* sqrt(Reff delta) delta         (8/15) Y* sqrt(Reff) delta^(5/2)
                  Y* = 1/((1 - nu_i^2)/Y_i + (1 - nu_j^2)/Y_j) = Y / (2 (1 - nu^2)) for one material
                  (LIGGGHTS 3.8 'gran model hertz', src/normal_model_hertz.h: kn = 4/3 Yeff sqrt(Reff
                  delta), F = kn delta; Yeff from src/global_properties.cpp createYeff)

so LIGGGHTS with (Y, nu) is LAMMPS Hertz with kn = hertz_kn_from_ymod(Y, nu) = 2 Y / (3 (1 - nu^2)).
k in the functions below is kn for 'hooke' and 'hertz_lammps' and Young's modulus Y for
'hertz_liggghts' (then poisson = nu is required; the LIGGGHTS input uses POISSON_LIGGGHTS).
"""
import math

import numpy as np

MODELS = ("hooke", "hertz_lammps", "hertz_liggghts")

# Poisson's ratio fixed in reference_inputs/liggghts/in.granular_hertz
POISSON_LIGGGHTS = 0.3

# integral_0^1 dx / sqrt(1 - x^(5/2)) = sqrt(pi) Gamma(7/5) / Gamma(9/10): the Hertz contact time
# in units of delta_max / v, halved
_HERTZ_HALF_TIME = math.sqrt(math.pi) * math.gamma(1.4) / math.gamma(0.9)


# --- conventions ---------------------------------------------------------------------------

def reduced_radius(ri, rj):
    """Reff = Ri Rj / (Ri + Rj) (arrays broadcast)."""
    return ri * rj / (ri + rj)


def effective_ymod(ymod, poisson):
    """Y* = Y / (2 (1 - nu^2)) of two spheres of the same material (LIGGGHTS Yeff)."""
    return ymod / (2.0 * (1.0 - poisson**2))


def hertz_kn_from_ymod(ymod, poisson=POISSON_LIGGGHTS):
    """LAMMPS gran/hertz/history kn with the same force law as LIGGGHTS hertz with (Y, nu)."""
    return 4.0 / 3.0 * effective_ymod(ymod, poisson)


def ymod_from_hertz_kn(kn, poisson=POISSON_LIGGGHTS):
    """Young's modulus for LIGGGHTS hertz that reproduces LAMMPS gran/hertz/history with kn."""
    return kn * 0.75 * 2.0 * (1.0 - poisson**2)


def _check_model(model, poisson):
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}, not {model!r}")
    if model == "hertz_liggghts" and poisson is None:
        raise ValueError("model 'hertz_liggghts' needs poisson")


def power_law(model, k, reff, poisson=None):
    """(A, p) with the pair energy u = A delta^p (A broadcasts with reff; reff unused for hooke)."""
    _check_model(model, poisson)
    if model == "hooke":
        return 0.5 * k * np.ones_like(np.asarray(reff, dtype=float)), 2.0
    kn = k if model == "hertz_lammps" else hertz_kn_from_ymod(k, poisson)
    return 0.4 * kn * np.sqrt(reff), 2.5


def pair_energy(delta, model, k, reff, poisson=None):
    """Elastic energy u(delta) of a pair (0 where delta <= 0)."""
    a, p = power_law(model, k, reff, poisson)
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    return a * d**p


def pair_force(delta, model, k, reff, poisson=None):
    """Repulsive normal force magnitude F = du/d(delta) (0 where delta <= 0)."""
    a, p = power_law(model, k, reff, poisson)
    d = np.maximum(np.asarray(delta, dtype=float), 0.0)
    return a * p * d**(p - 1.0)


# --- Barker-Henderson shift -----------------------------------------------------------------

def bh_shift(a, p, kT=1.0):
    """Delta = integral_0^inf exp(-a delta^p / kT) d(delta) = Gamma(1 + 1/p) (kT / a)^(1/p).

    The BH diameter of a pair with contact distance sigma_ij is d = integral_0^sigma_ij
    [1 - exp(-u(r)/kT)] dr = sigma_ij - Delta (the upper limit delta = sigma_ij taken to infinity,
    an error of exp(-u(sigma_ij)/kT), negligible for any useful stiffness)."""
    return math.gamma(1.0 + 1.0 / p) * (kT / a)**(1.0 / p)


def bh_shift_hooke(kn, kT=1.0):
    """Delta for u = kn delta^2 / 2: sqrt(pi kT / (2 kn))."""
    return math.sqrt(math.pi * kT / (2.0 * kn))


def bh_shift_hertz_lammps(kn, reff, kT=1.0):
    """Delta for LAMMPS gran/hertz/history: u = (2/5) kn sqrt(Reff) delta^(5/2)."""
    return bh_shift(0.4 * kn * math.sqrt(reff), 2.5, kT)


def bh_shift_hertz_liggghts(ymod, poisson, reff, kT=1.0):
    """Delta for LIGGGHTS hertz: u = (8/15) Y* sqrt(Reff) delta^(5/2), Y* = Y / (2 (1 - nu^2))."""
    return bh_shift(8.0 / 15.0 * effective_ymod(ymod, poisson) * math.sqrt(reff), 2.5, kT)


# --- configurations -------------------------------------------------------------------------

def close_pairs(pos, box_lo, box_hi, rmax):
    """Pairs of a fully periodic configuration closer than rmax (minimum image).

    Returns (i, j, rij, r): index arrays with i < j, separation vectors rij = pos[i] - pos[j]
    (shape (M, 3)) and their lengths. Positions may lie outside the box (unwrapped dump
    coordinates); they are wrapped first."""
    from scipy.spatial import cKDTree

    pos = np.asarray(pos, dtype=float)
    lo = np.asarray(box_lo, dtype=float)
    length = np.asarray(box_hi, dtype=float) - lo
    x = np.mod(pos - lo, length)
    x[x >= length] = 0.0  # mod can round up to exactly L
    if len(x) < 2:
        empty = np.zeros(0, dtype=int)
        return empty, empty, np.zeros((0, 3)), np.zeros(0)
    pairs = cKDTree(x, boxsize=length).query_pairs(rmax, output_type="ndarray").reshape(-1, 2)
    i, j = pairs[:, 0], pairs[:, 1]
    rij = x[i] - x[j]
    rij -= length * np.round(rij / length)
    return i, j, rij, np.sqrt(np.einsum("ij,ij->i", rij, rij))


def contacts(pos, radius, box_lo, box_hi):
    """Overlapping pairs of a fully periodic configuration: close_pairs within the contact
    distance, with their overlaps. Returns (i, j, rij, r, delta), delta = R_i + R_j - r > 0."""
    radius = np.asarray(radius, dtype=float)
    i, j, rij, r = close_pairs(pos, box_lo, box_hi, 2.0 * radius.max() if len(radius) else 0.0)
    delta = radius[i] + radius[j] - r
    keep = delta > 0
    return i[keep], j[keep], rij[keep], r[keep], delta[keep]


def elastic_energy(pos, radius, box_lo, box_hi, model, k, poisson=None):
    """Total elastic overlap energy sum_{i<j} u(delta_ij) of a periodic configuration."""
    i, j, _, _, delta = contacts(pos, radius, box_lo, box_hi)
    reff = reduced_radius(np.asarray(radius)[i], np.asarray(radius)[j])
    return float(np.sum(pair_energy(delta, model, k, reff, poisson)))


def pair_virial(pos, radius, box_lo, box_hi, model, k, poisson=None):
    """W = sum over contacts of r_ij . F_ij (F_ij the force on i from j, r_ij = r_i - r_j), which
    is r F(delta) for central repulsive forces. The virial pressure is W / (3 V)."""
    i, j, _, r, delta = contacts(pos, radius, box_lo, box_hi)
    reff = reduced_radius(np.asarray(radius)[i], np.asarray(radius)[j])
    return float(np.sum(r * pair_force(delta, model, k, reff, poisson)))


# --- head-on contact ------------------------------------------------------------------------

def contact_time_hooke(kn, meff):
    """Duration of a Hookean contact, independent of speed: pi sqrt(meff / kn)."""
    return math.pi * math.sqrt(meff / kn)


def max_overlap_hertz(stiffness, meff, v):
    """Largest overlap of a head-on Hertz contact F = K delta^(3/2) at approach speed v:
    (1/2) meff v^2 = (2/5) K delta_max^(5/2)."""
    return (1.25 * meff * v * v / stiffness)**0.4


def contact_time_hertz(stiffness, meff, v):
    """Duration of a head-on Hertz contact F = K delta^(3/2) (K = stiffness) at relative normal
    speed v: t_c = 2 (delta_max / v) integral_0^1 dx / sqrt(1 - x^(5/2))
                 = 2.9432 delta_max / v = 3.2181 (meff / K)^(2/5) v^(-1/5).
    (The often-quoted 2.94 multiplies delta_max / v; with F = 4/3 E* sqrt(R*) delta^(3/2) it is
    the textbook 2.87 (meff^2 / (R* E*^2 v))^(1/5).) K is kn sqrt(Reff) for LAMMPS
    gran/hertz/history and 4/3 Y* sqrt(Reff) for LIGGGHTS hertz (hertz_stiffness)."""
    return 2.0 * _HERTZ_HALF_TIME * max_overlap_hertz(stiffness, meff, v) / v


def gamman_for_restitution(e, kn, meff):
    """LAMMPS gran/hooke gamman (1/time) that gives restitution e: the head-on contact is
    delta'' + gamman delta' + (kn/meff) delta = 0, e = exp(-gamman t_c / 2) with
    t_c = pi / sqrt(kn/meff - gamman^2/4), so gamman = 2 |ln e| sqrt(kn/meff) / sqrt(pi^2 + ln^2 e)."""
    if not 0 < e <= 1:
        raise ValueError(f"restitution must be in (0, 1], not {e}")
    le = math.log(e)
    return -2.0 * le * math.sqrt(kn / meff) / math.sqrt(math.pi**2 + le * le)


def hooke_contact_time(gamman, kn, meff):
    """Duration of a damped linear contact, delta = 0 to delta = 0: pi / sqrt(kn/meff - gamman^2/4)."""
    return math.pi / math.sqrt(kn / meff - gamman * gamman / 4.0)


def hooke_restitution(gamman, kn, meff):
    """Restitution of the linear spring-dashpot: exp(-gamman t_c / 2)."""
    return math.exp(-gamman * hooke_contact_time(gamman, kn, meff) / 2.0)


def sticking_beta0(kt, contact_time, meff, q=0.4):
    """Walton's sticking limit beta0 of a linear tangential spring kt: a sticking contact's
    tangential contact velocity oscillates with omega_t = sqrt(kt (1 + q) / (q meff)) (the mass
    meff q / (1 + q)), so after a contact of duration t_c it is cos(omega_t t_c) times what it was:
    beta0 = -cos(omega_t t_c)."""
    return -math.cos(math.sqrt(kt * (1 + q) / (q * meff)) * contact_time)


def hertz_stiffness(model, k, reff, poisson=None):
    """K of F = K delta^(3/2) for a pair: kn sqrt(Reff) or 4/3 Y* sqrt(Reff)."""
    a, p = power_law(model, k, reff, poisson)
    if p != 2.5:
        raise ValueError("hertz_stiffness needs a Hertz model")
    return a * p


# --- engine output --------------------------------------------------------------------------

def read_blocks(path):
    """The virialfile of the reference inputs as an (nblocks, 3) array: step, block mean of the
    virial pressure, block mean of thermo_temp (sum m v^2 / (3N - 3))."""
    return np.loadtxt(path, comments="#", ndmin=2)
