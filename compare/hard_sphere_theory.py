"""Hard-sphere reference values for additive mixtures (one species = the monodisperse fluid).

Species are given as (number fraction, diameter, mass); kT = 1 unless given. Formulas:
Boublik-Mansoori-Carnahan-Starling-Leland (BMCSL) pressure and contact values (Carnahan-Starling
for one species), Enskog collision rate and, for one species, Enskog's self-diffusion coefficient.
"""
import math


def _xi(density, species):
    """xi_k = (pi/6) n sum x_i d_i^k for k = 0..3."""
    return [math.pi / 6 * density * sum(x * d**k for x, d, _ in species) for k in range(4)]


def packing_fraction(density, species):
    return _xi(density, species)[3]


def density_at(phi, species):
    """Number density of the mixture at packing fraction phi."""
    return phi / (math.pi / 6 * sum(x * d**3 for x, d, _ in species))


def z_bmcsl(phi, species):
    """Compressibility factor PV/NkT (Carnahan-Starling for one species)."""
    x0, x1, x2, x3 = _xi(density_at(phi, species), species)
    return (x0 / (1 - x3) + 3 * x1 * x2 / (1 - x3) ** 2 + (3 - x3) * x2**3 / (1 - x3) ** 3) / x0


def contact_value(phi, species, i, j):
    """g_ij at contact, BMCSL (Boublik; Grundke-Henderson form)."""
    _, _, x2, x3 = _xi(density_at(phi, species), species)
    di, dj = species[i][1], species[j][1]
    a = di * dj / (di + dj)
    return 1 / (1 - x3) + 3 * x2 * a / (1 - x3) ** 2 + 2 * x2**2 * a**2 / (1 - x3) ** 3


def enskog_rate(phi, species, kT=1.0, contact=None):
    """Collisions per particle per unit time (each collision counted for both spheres).

    contact(i, j) overrides the contact values (e.g. measured ones); default BMCSL."""
    n = density_at(phi, species)
    g = contact or (lambda i, j: contact_value(phi, species, i, j))
    rate = 0.0
    for i, (xi, di, mi) in enumerate(species):
        for j, (xj, dj, mj) in enumerate(species):
            sij, mu = (di + dj) / 2, mi * mj / (mi + mj)
            rate += xi * xj * n * sij**2 * g(i, j) * math.sqrt(8 * math.pi * kT / mu)
    return rate


def enskog_diffusion(phi, diameter=1.0, mass=1.0, kT=1.0, contact=None):
    """Enskog self-diffusion coefficient of the one-species fluid (first Sonine approximation)."""
    species = [(1.0, diameter, mass)]
    n = density_at(phi, species)
    g = contact if contact is not None else contact_value(phi, species, 0, 0)
    return 3 / (8 * n * diameter**2 * g) * math.sqrt(kT / (math.pi * mass))
