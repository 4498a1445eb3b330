"""Hard-sphere kinetic theory: the formulas every validation compares with (the runners import
them; nothing here runs a program).

Species are given as (number fraction, diameter, mass); kT = 1 unless given. Formulas:
- equilibrium: Boublik-Mansoori-Carnahan-Starling-Leland (BMCSL) pressure and contact values
  (Carnahan-Starling for one species), Kolafa's correction to Carnahan-Starling;
- collisions: Enskog's collision rate (from the contact value or from a measured Z), the mean
  relative speed of a Maxwellian pair;
- transport: Enskog's self-diffusion coefficient, the heavy tracer's (Brownian) diffusion
  coefficient and collision rate, Enskog's shear viscosity, slip Stokes-Einstein in a periodic box;
- inelastic spheres: Haff's law of a cooling gas, the homogeneous cooling state's Sonine
  coefficient a2 (van Noije and Ernst), the barometric mean height under gravity.
Rough spheres: compare.rough_theory; soft-sphere contacts: compare.soft_spheres.
"""
import math

import numpy as np

XI_CUBIC = 2.837297  # Hasimoto's constant of a periodic cube (finite-box diffusion correction)


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


# --- one species, unit diameter and mass -------------------------------------------------------

def contact_value_cs(phi):
    """Carnahan-Starling g(sigma) = (1 - phi/2) / (1 - phi)^3."""
    return (1 - phi / 2) / (1 - phi) ** 3


def z_carnahan_starling(eta):
    """Carnahan-Starling Z = (1 + eta + eta^2 - eta^3) / (1 - eta)^3."""
    return (1 + eta + eta**2 - eta**3) / (1 - eta) ** 3


def z_kolafa(eta):
    """Kolafa's correction to Carnahan-Starling (Boublik & Nezbeda, Collect. Czech. Chem. Commun. 51,
    2301 (1986)), which follows precise event-driven data to about 0.05% in the stable fluid."""
    return (1 + eta + eta**2 - 2.0 / 3.0 * eta**3 * (1 + eta)) / (1 - eta) ** 3


def enskog_rate_from_z(eta, z, temperature=1.0, mass=1.0):
    """Enskog collisions per particle per unit time, sigma = 1, with g(sigma) = (Z - 1)/(4 eta)."""
    n = 6 * eta / math.pi
    g = (z - 1) / (4 * eta)
    return 4 * n * math.sqrt(math.pi * temperature / mass) * g


def mean_relative_speed(kT, meff):
    """<|v_i - v_j|> of a Maxwellian pair of reduced mass meff: sqrt(8 kT / (pi meff))."""
    return math.sqrt(8.0 * kT / (math.pi * meff))


# --- a heavy tracer (Brownian motion) ----------------------------------------------------------

def heavy_tracer(phi, n_small, d_big, m_big, length, kT):
    """Enskog's heavy-tracer values and Stokes-Einstein's for one big sphere (diameter d_big, mass
    m_big) among n_small unit spheres in a periodic cube of side length:
    D_E = 3 kT / (8 n sigma12^2 g12 sqrt(2 pi mu kT)), Gamma12 = n sigma12^2 g12 sqrt(8 pi kT / mu)
    (g12 BMCSL), the small-sphere fluid's Enskog shear viscosity eta, slip Stokes-Einstein with the
    finite-box correction D_SE = kT / (4 pi eta sigma12) - kT xi / (6 pi eta L), the velocity
    relaxation time tau = M D_E / kT and the zero-total-momentum factor (1 - M / M_tot)^2."""
    n_tot = n_small + 1
    species = [(n_small / n_tot, 1.0, 1.0), (1 / n_tot, d_big, m_big)]
    g12 = contact_value(phi, species, 0, 1)
    density = n_small / length**3
    sigma12 = (d_big + 1) / 2
    mu = m_big / (m_big + 1)
    d_enskog = 3 * kT / (8 * density * sigma12**2 * g12 * math.sqrt(2 * math.pi * mu * kT))
    gamma_enskog = density * sigma12**2 * g12 * math.sqrt(8 * math.pi * kT / mu)
    eta = enskog_viscosity(density, kT)
    d_se = kT / (4 * math.pi * eta * sigma12) - kT * XI_CUBIC / (6 * math.pi * eta * length)
    return dict(g12=g12, n=density, sigma12=sigma12, mu=mu, D_enskog=d_enskog, Gamma12_enskog=gamma_enskog,
                eta=eta, D_stokes_einstein=d_se, tau=m_big * d_enskog / kT,
                momentum_factor=(1 - m_big / (m_big + n_small)) ** 2)


def enskog_viscosity(density, kT=1.0):
    """Enskog's shear viscosity of unit spheres at number density n (with their own contact value)."""
    phi_s = math.pi / 6 * density
    g11 = (1 - phi_s / 2) / (1 - phi_s) ** 3
    eta0 = 1.016 * 5 / 16 * math.sqrt(kT / math.pi)
    b = 4 * phi_s
    return eta0 * (1 / g11 + 0.8 * b + 0.7614 * b * b * g11)


# Converged Sonine factors of the dilute gas over the first approximation (Chapman and Cowling):
# D, eta, lambda.
SONINE_D, SONINE_ETA, SONINE_LAMBDA = 1.01896, 1.01600, 1.02513


def enskog_transport(phi, contact=None):
    """Enskog's D_E, eta_E and lambda_E of unit spheres (sigma = m = kT = 1) at packing fraction
    phi, g Carnahan-Starling's contact value unless given, the dilute values with their converged
    Sonine factors: D_E = D0 / g, eta_E = eta0 (1/g + 0.8 b + 0.7614 b^2 g),
    lambda_E = lambda0 (1/g + 1.2 b + 0.7574 b^2 g), b rho = 4 phi."""
    g = contact if contact is not None else contact_value_cs(phi)
    n = 6 * phi / math.pi
    b = 4 * phi
    d0 = SONINE_D * 3 / (8 * n) / math.sqrt(math.pi)
    eta0 = SONINE_ETA * 5 / 16 / math.sqrt(math.pi)
    lam0 = SONINE_LAMBDA * 75 / 64 / math.sqrt(math.pi)
    return dict(D=d0 / g, eta=eta0 * (1 / g + 0.8 * b + 0.7614 * b * b * g),
                lam=lam0 * (1 / g + 1.2 * b + 0.7574 * b * b * g), g=g, n=n)


def free_path(n):
    """Mean free path of a dilute gas of unit spheres at number density n."""
    return 1 / (math.sqrt(2) * math.pi * n)


# --- inelastic spheres -------------------------------------------------------------------------

def haff_temperature(t, t0, e, gamma0):
    """Haff's law T0 / (1 + (1 - e^2) Gamma0 t / 6)^2, Gamma0 the collision rate per particle at T0
    (t may be an array)."""
    return t0 / (1.0 + (1.0 - e * e) * gamma0 * np.asarray(t, dtype=float) / 6.0) ** 2


def haff_time(fraction, e, gamma0):
    """Time at which Haff's law reaches T = fraction T0 (e < 1)."""
    return (1.0 / math.sqrt(fraction) - 1.0) * 6.0 / ((1.0 - e * e) * gamma0)


def haff_time_for_collisions(collisions_per_sphere, e, gamma0):
    """Time in which a gas cooling by Haff's law makes this many collisions per sphere: the rate
    Gamma0 sqrt(T/T0) integrates to ln(1 + eps Gamma0 t) / eps, eps = (1 - e^2) / 6."""
    eps = (1 - e * e) / 6
    return (math.exp(eps * collisions_per_sphere) - 1) / (eps * gamma0)


def a2_van_noije_ernst(e):
    """The homogeneous cooling state's second Sonine coefficient in the first Sonine approximation
    (van Noije and Ernst 1998, three dimensions)."""
    return 16 * (1 - e) * (1 - 2 * e * e) / (81 - 17 * e + 30 * e * e * (1 - e))


def barometric_mean_height(h, height):
    """Mean height above the floor of an ideal gas with scale height h = T / (m g) between walls
    `height` apart (contact to contact): h - H / (exp(H / h) - 1)."""
    return h - height / math.expm1(height / h)
