"""Kinetic theory of the homogeneous cooling of rough inelastic hard spheres (one species, mass m,
diameter d = 2a, moment of inertia I = q m a^2), k_B = 1, under molecular chaos and Maxwellian
velocity and angular velocity distributions at the temperatures T (translational) and T_rot.

The collision rule is the project's (docs of issue 37): g = v_i - v_j - a (w_i + w_j) x n,
J_n = -(1 + e) mu (g.n) n, J_t = -(1 + beta) q mu / (1 + q) g_t (mu = m/2), and with Walton's
friction J_t = -mu_f |J_n| g_t / |g_t| when that is smaller than the constant-beta impulse.

Constant beta, with eta = q (1 + beta) / (2 (1 + q)) (Huthmann and Zippelius 1997; Luding,
Huthmann, McNamara and Zippelius 1998), derived from that rule: per collision, averaged over
Maxwellian pairs weighted by |g.n|,
    <dE_tr> = -4 (A T - B T_rot),  <dE_rot> = 4 (B T - C T_rot),
    A = (1 - e^2)/4 + eta (1 - eta),  B = eta^2 / q,  C = (eta / q) (1 - eta / q),
and, with omega(T) = 4 n d^2 chi sqrt(pi T / m) collisions per sphere per unit time (chi the
Carnahan-Starling contact value) and (3/2) dT/dt = (omega / 2) <dE>:
    dT/dt = -(4/3) omega(T) (A T - B T_rot),  dT_rot/dt = (4/3) omega(T) (B T - C T_rot).
The scaling state has R = T_rot / T constant: B R^2 + (C - A) R - B = 0, the positive root.

Walton's friction has no closed form at every mu under this closure: the per-collision averages
come from a Monte Carlo of the rule itself (energy_changes), homogeneous of degree one in the
temperatures, so <dE>(T, T_rot) = T <dE>(1, T_rot / T). Its asymptotes (McNamara and Luding
1998): large mu, every contact sticks, the constant-beta theory at beta0; small mu, every contact
slides (J_t = -mu_f (1 + e) mu |g.n| g_t/|g_t|), for which (sliding_changes)
    <dE_tr> = -(1 - e^2) T - mu_f (1 + e) (pi/2) T^(3/2) / s + mu_f^2 (1 + e)^2 T,
    <dE_rot> = -mu_f (1 + e) (pi/2) T^(1/2) (T_rot / q) / s + mu_f^2 (1 + e)^2 T / q,
    s = sqrt(T + T_rot / q).

Sonine corrections (Santos, Kremer and dos Santos 2011): the one-particle distribution
f = f_M(c) f_M(w) [1 + a20 S2(c^2) + a02 S2(w^2) + a11 S1(c^2) S1(w^2)], c^2 = m v^2 / 2T,
w^2 = I w^2 / 2T_rot, S1(x) = 3/2 - x, S2(x) = x^2/2 - 5x/2 + 15/8; energy_changes takes the
cumulants (measured ones) and weights its Maxwellian samples by f / f_M, which gives the
collisional moments to first order in the cumulants.

Importing this module has no side effects.
"""
import math

import numpy as np
from scipy import integrate, optimize

from compare import hard_sphere_theory as hs_theory


# --- constant tangential restitution -----------------------------------------------------------

def eta(beta, q=0.4):
    return q * (1.0 + beta) / (2.0 * (1.0 + q))


def coefficients(e, beta, q=0.4):
    """(A, B, C) of the constant-beta energy balance per collision."""
    h = eta(beta, q)
    return (1.0 - e * e) / 4.0 + h * (1.0 - h), h * h / q, (h / q) * (1.0 - h / q)


def scaling_ratio(e, beta, q=0.4):
    """T_rot / T of the scaling state: the positive root of B R^2 + (C - A) R - B = 0 (infinite for
    beta = -1 with e < 1: the smooth gas's rotation does not cool)."""
    a, b, c = coefficients(e, beta, q)
    if b == 0.0:
        return math.inf if a > c else 0.0
    return (a - c + math.sqrt((a - c) ** 2 + 4.0 * b * b)) / (2.0 * b)


def cooling_rate(e, beta, q=0.4):
    """zeta / omega of the scaling state: dT/dt = -zeta T, zeta = (4/3) omega (A - B R)."""
    a, b, _ = coefficients(e, beta, q)
    return 4.0 / 3.0 * (a - b * scaling_ratio(e, beta, q))


def collision_rate(phi, t, mass=1.0):
    """omega = 4 n d^2 chi sqrt(pi T / m) of unit-diameter spheres (Carnahan-Starling chi)."""
    return hs_theory.enskog_rate(phi, [(1.0, 1.0, mass)], kT=t)


def constant_beta_rates(e, beta, q=0.4):
    """(h_tr, h_rot)(R): <dE_tr>, <dE_rot> per collision at T = 1, T_rot = R."""
    a, b, c = coefficients(e, beta, q)
    return lambda r: (-4.0 * (a - b * r), 4.0 * (b - c * r))


def sliding_rates(e, mu_f, q=0.4):
    """(h_tr, h_rot)(R) when every contact slides (Walton, small mu), T = 1, T_rot = R."""
    def h(r):
        s = math.sqrt(1.0 + r / q)
        k = mu_f * (1.0 + e)
        return (-(1.0 - e * e) - k * math.pi / 2.0 / s + k * k, -k * math.pi / 2.0 * (r / q) / s + k * k / q)
    return h


def ratio_of_rates(h, r_min=1e-3, r_max=1e2, points=26):
    """The scaling state of per-collision rates h(R) = (<dE_tr>, <dE_rot>) at T = 1: the smallest
    stable R where T_rot and T cool at the same relative rate, <dE_rot> / R = <dE_tr> (R grows where
    f(R) = <dE_rot> / R - <dE_tr> > 0). None when there is none in [r_min, r_max]: the rotation cools
    more slowly than the translation and R grows without bound (near-smooth spheres)."""
    def f(r):
        tr, rot = h(r)
        return rot / r - tr
    grid = np.geomspace(r_min, r_max, points)
    values = [f(r) for r in grid]
    for k in range(points - 1):
        if values[k] > 0 >= values[k + 1]:
            return optimize.brentq(f, grid[k], grid[k + 1], xtol=1e-12, rtol=1e-10)
    return None


def temperatures(times, phi, t0, r0, h, mass=1.0):
    """T(t), T_rot(t) from T(0) = t0, T_rot(0) = r0 t0, with the per-collision rates h(R) at T = 1:
    (3/2) dT/dt = (omega(T) / 2) T h_tr(T_rot / T), likewise T_rot."""
    w1 = collision_rate(phi, 1.0, mass)

    def rhs(_, y):
        t, tr = y
        om = w1 * math.sqrt(max(t, 0.0))
        a, b = h(tr / t)
        return [om * t * a / 3.0, om * t * b / 3.0]
    times = np.asarray(times, dtype=float)
    sol = integrate.solve_ivp(rhs, (0.0, float(times.max())), [t0, r0 * t0], t_eval=times, rtol=1e-10,
                              atol=1e-13 * t0, method="DOP853")
    return sol.y[0], sol.y[1]


def time_to_fraction(fraction, phi, t0, r0, h, mass=1.0):
    """The time at which T reaches fraction t0 in temperatures()."""
    w1 = collision_rate(phi, 1.0, mass)

    def rhs(_, y):
        a, b = h(y[1] / y[0])
        om = w1 * math.sqrt(y[0])
        return [om * y[0] * a / 3.0, om * y[0] * b / 3.0]

    def hit(_, y):
        return y[0] - fraction * t0
    hit.terminal = True
    sol = integrate.solve_ivp(rhs, (0.0, 1e7), [t0, r0 * t0], events=hit, rtol=1e-10, atol=1e-13 * t0,
                              method="DOP853")
    return float(sol.t_events[0][0])


# --- the collision rule, sampled -------------------------------------------------------------

def collide(v1, v2, w1, w2, n, e, beta, q=0.4, mu_f=math.inf, radius=0.5, mass=1.0, sliding_only=False):
    """The contract's collision of equal spheres (arrays of rows): new v1, v2, w1, w2. n points from
    sphere 2 to sphere 1. sliding_only applies the Coulomb impulse to every contact."""
    inertia = q * mass * radius * radius
    mu = mass / 2.0
    g = v1 - v2 - radius * np.cross(w1 + w2, n)
    gn = (g * n).sum(axis=1, keepdims=True)
    gt = g - gn * n
    jn = -(1.0 + e) * mu * gn * n
    jt = -(1.0 + beta) * q * mu / (1.0 + q) * gt
    if math.isfinite(mu_f) or sliding_only:
        limit = mu_f * np.linalg.norm(jn, axis=1, keepdims=True)
        gtn = np.linalg.norm(gt, axis=1, keepdims=True)
        slide = np.ones_like(limit, dtype=bool) if sliding_only else np.linalg.norm(jt, axis=1, keepdims=True) > limit
        with np.errstate(invalid="ignore", divide="ignore"):
            jslide = np.where(gtn > 0, -limit * gt / gtn, 0.0)
        jt = np.where(slide, jslide, jt)
    j = jn + jt
    dw = -radius * np.cross(n, j) / inertia
    return v1 + j / mass, v2 - j / mass, w1 + dw, w2 + dw


def _sonine_weight(c2, w2, a20, a02, a11):
    s1c, s1w = 1.5 - c2, 1.5 - w2
    s2c, s2w = c2 * c2 / 2 - 2.5 * c2 + 15 / 8, w2 * w2 / 2 - 2.5 * w2 + 15 / 8
    return 1.0 + a20 * s2c + a02 * s2w + a11 * s1c * s1w


def draw(samples, rng):
    """Standard normal velocities and angular velocities of the two spheres (2, samples, 3) each,
    and unit normals (samples, 3), to be scaled to the temperatures by energy_changes."""
    v = rng.normal(size=(2, samples, 3))
    w = rng.normal(size=(2, samples, 3))
    n = rng.normal(size=(samples, 3))
    return v, w, n / np.linalg.norm(n, axis=1, keepdims=True)


def energy_changes(samples, r, e, beta, q=0.4, mu_f=math.inf, rng=None, cumulants=None, sliding_only=False,
                   radius=0.5, mass=1.0, drawn=None):
    """Monte Carlo of <dE_tr>, <dE_rot> per collision (the pair's energy changes averaged over
    collisions: pairs weighted by |g.n|) at T = 1, T_rot = r, Maxwellian, or Sonine-corrected with
    cumulants = (a20, a02, a11). drawn: draw()'s samples to reuse. Returns dict tr, rot (the
    means), tr_err, rot_err (their standard errors) and frequency (the collision frequency over
    the Maxwellian one: 1 without cumulants)."""
    if drawn is None:
        drawn = draw(samples, np.random.default_rng(1) if rng is None else rng)
    inertia = q * mass * radius * radius
    v = drawn[0] * math.sqrt(1.0 / mass)
    w = drawn[1] * math.sqrt(r / inertia)
    n = drawn[2]
    v1, v2, w1, w2 = collide(v[0], v[1], w[0], w[1], n, e, beta, q, mu_f, radius, mass, sliding_only)
    speed = np.abs(((v[0] - v[1]) * n).sum(axis=1))
    weight = speed
    if cumulants is not None:
        a20, a02, a11 = cumulants
        for k in range(2):
            c2 = mass * (v[k] ** 2).sum(axis=1) / 2.0
            x2 = (drawn[1][k] ** 2).sum(axis=1) / 2.0
            weight = weight * _sonine_weight(c2, x2, a20, a02, a11)
    de_tr = mass / 2 * ((v1 ** 2).sum(axis=1) + (v2 ** 2).sum(axis=1) - (v[0] ** 2 + v[1] ** 2).sum(axis=1))
    de_rot = inertia / 2 * ((w1 ** 2).sum(axis=1) + (w2 ** 2).sum(axis=1) - (w[0] ** 2 + w[1] ** 2).sum(axis=1))
    out = {}
    wsum = weight.sum()
    for name, x in (("tr", de_tr), ("rot", de_rot)):
        out[name] = mean = float((weight * x).sum() / wsum)
        out[name + "_err"] = float(math.sqrt(((weight * (x - mean)) ** 2).sum()) / wsum)  # ratio estimator
    out["frequency"] = float(wsum / speed.sum())
    return out


def sampled_rates(e, beta, q=0.4, mu_f=math.inf, samples=400000, seed=7, cumulants=None, sliding_only=False):
    """(h_tr, h_rot)(R) from energy_changes with the same random numbers at every R (a smooth
    function of R for root finding), times the relative collision frequency (cumulants)."""
    drawn = draw(samples, np.random.default_rng(seed))

    def h(r):
        x = energy_changes(samples, r, e, beta, q, mu_f, cumulants=cumulants, sliding_only=sliding_only, drawn=drawn)
        return x["tr"] * x["frequency"], x["rot"] * x["frequency"]
    return h


def tabulated(h, r_min=0.01, r_max=5.0, points=60):
    """h on a logarithmic grid of R, interpolated (for ODE integration of a sampled h)."""
    grid = np.geomspace(r_min, r_max, points)
    values = np.array([h(r) for r in grid])

    def f(r):
        x = math.log(min(max(r, r_min), r_max))
        lg = np.log(grid)
        return float(np.interp(x, lg, values[:, 0])), float(np.interp(x, lg, values[:, 1]))
    return f


# --- measured quantities ---------------------------------------------------------------------

def cumulants_of(vel, omega, mass, inertia):
    """(a20, a02, a11) of one frame: a20 = (4/15) <c^4> - 1, a02 likewise for w, a11 =
    (4/9) <c^2 w^2> - 1, with c^2 = m v^2 / 2T and w^2 = I w^2 / 2T_rot (v peculiar)."""
    vel = vel - (mass[:, None] * vel).sum(axis=0) / mass.sum()
    ev = mass * (vel ** 2).sum(axis=1)
    ew = inertia * (omega ** 2).sum(axis=1)
    c2 = ev / (2 * ev.mean() / 3)
    x2 = ew / (2 * ew.mean() / 3)
    return (float(4 / 15 * np.mean(c2 ** 2) - 1), float(4 / 15 * np.mean(x2 ** 2) - 1),
            float(4 / 9 * np.mean(c2 * x2) - 1))


def temperatures_of(vel, omega, mass, inertia):
    """(T_tr, T_rot) of a frame: sum m |v - v_cm|^2 / 3N and sum I |w|^2 / 3N."""
    vel = vel - (mass[:, None] * vel).sum(axis=0) / mass.sum()
    n = len(mass)
    return (float((mass * (vel ** 2).sum(axis=1)).sum() / (3 * n)),
            float((inertia * (omega ** 2).sum(axis=1)).sum() / (3 * n)))
