"""Observables from trajectory frames, the same code for every engine (cross-validation).

A frame is a dict with t (simulated time), box lo/hi (3,), ids, types, radius, pos (N,3),
vel (N,3), all sorted by id, and `unwrapped` True when pos are unwrapped coordinates.
"""
import math

import numpy as np
from scipy import stats

from compare import soft_spheres
from compare.lammps_files import read_dump


def iter_frames(path, dt=None, times=None):
    """The frames of a LAMMPS text dump (lammps_files.read_dump) as this module's frames, one at a
    time; t = timestep * dt, or times[k] for frame k."""
    for k, c in enumerate(read_dump(path)):
        yield dict(t=times[k] if times is not None else c.timestep * (dt or 0.0), step=c.timestep, lo=c.box_lo,
                   hi=c.box_hi, ids=c["id"], types=c["type"], radius=c["radius"], pos=c.positions(),
                   vel=np.column_stack([c["vx"], c["vy"], c["vz"]]) if "vx" in c else None,
                   unwrapped=c.unwrapped)


def read_frames(path, dt=None, times=None):
    return list(iter_frames(path, dt, times))


def unwrap(frames):
    """Unwrapped positions (F, N, 3): kept as they are, or by the minimum image between frames
    (valid while no sphere moves half a box between frames; checked against the fastest speed)."""
    pos = np.array([f["pos"] for f in frames])
    if frames[0]["unwrapped"]:
        return pos
    length = frames[0]["hi"] - frames[0]["lo"]
    step = np.diff(pos, axis=0)
    step -= length * np.round(step / length)
    return np.concatenate([pos[:1], pos[0] + np.cumsum(step, axis=0)])


def msd_diffusion(frames, window, groups=8):
    """Mean-squared displacement over all time origins, and D from its slope over lags in `window`
    (t_lo, t_hi), the same window for every engine of a state.

    Returns (lags, msd, D, D_err); D and D_err are None when fewer than 3 lags fall in the window.
    D_err from the spread of D over `groups` disjoint sets of spheres."""
    pos = unwrap(frames)
    times = np.array([f["t"] for f in frames])
    lags = np.arange(1, len(frames))
    tau = times[lags] - times[0]
    lags, tau = lags[tau <= window[1] * 1.0001], tau[tau <= window[1] * 1.0001]
    if len(lags) < 3:  # frames too far apart for the window
        return tau, np.zeros(len(lags)), None, None
    per_sphere = np.array([((pos[k:] - pos[:-k]) ** 2).sum(axis=2).mean(axis=0) for k in lags])  # (lags, N)
    msd = per_sphere.mean(axis=1)
    fit = tau >= window[0] * 0.9999
    if fit.sum() < 3:
        return tau, msd, None, None

    def slope(m):
        return np.polyfit(tau[fit], m[fit], 1)[0] / 6

    parts = np.array_split(np.arange(per_sphere.shape[1]), groups)
    ds = np.array([slope(per_sphere[:, p].mean(axis=1)) for p in parts])
    return tau, msd, slope(msd), ds.std(ddof=1) / math.sqrt(groups)


def reduced_speeds(frame, mass):
    """Speeds scaled to unit mass and unit temperature: v sqrt(m / T), T = <m v^2> / 3."""
    v2 = (frame["vel"] ** 2).sum(axis=1)
    temperature = (mass * v2).mean() / 3
    return np.sqrt(mass * v2 / temperature), temperature


def speed_ks(frame, mass):
    """KS test of one frame's speeds (N independent samples) against Maxwell-Boltzmann."""
    u, temperature = reduced_speeds(frame, mass)
    res = stats.kstest(u, stats.maxwell.cdf)
    return res.statistic, res.pvalue, temperature


def pair_distances(frame, rmax):
    """Distances and sphere indices (M, 2) of all pairs closer than rmax (periodic, minimum image)."""
    i, j, _, r = soft_spheres.close_pairs(frame["pos"], frame["lo"], frame["hi"], rmax)
    return r, np.column_stack([i, j])


def rdf(frames, rmax=3.0, width=0.01):
    """g(r) per pair of types from the given frames: {(a, b): (r, g, counts)} plus 'all'."""
    f0 = frames[0]
    length = f0["hi"] - f0["lo"]
    rmax = min(rmax, 0.5 * length.min())
    edges = np.arange(0.0, rmax + width / 2, width)
    shell = 4 / 3 * math.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    volume = float(np.prod(length))
    types = sorted(set(f0["types"].tolist()))
    count = {t: int((f0["types"] == t).sum()) for t in types}
    keys = [(a, b) for a in types for b in types if a <= b]
    hist = {k: np.zeros(len(edges) - 1) for k in keys}
    for f in frames:
        r, pairs = pair_distances(f, rmax)
        ta, tb = f["types"][pairs[:, 0]], f["types"][pairs[:, 1]]
        lo_t, hi_t = np.minimum(ta, tb), np.maximum(ta, tb)
        for a, b in keys:
            sel = (lo_t == a) & (hi_t == b)
            hist[(a, b)] += np.histogram(r[sel], edges)[0]
    centres = 0.5 * (edges[1:] + edges[:-1])
    out = {}
    total = np.zeros_like(centres)
    for a, b in keys:
        npairs = count[a] * (count[a] - 1) / 2 if a == b else count[a] * count[b]
        ideal = npairs * shell / volume * len(frames)
        out[(a, b)] = (centres, hist[(a, b)] / ideal, hist[(a, b)])
        total += hist[(a, b)]
    n = len(f0["ids"])
    out["all"] = (centres, total / (n * (n - 1) / 2 * shell / volume * len(frames)), total)
    return out


def contact_value(r, g, counts, sigma, span=0.08):
    """g at r = sigma from outside: a weighted straight-line fit over (sigma, sigma + span)."""
    sel = (r > sigma) & (r < sigma + span) & (counts > 0)
    if sel.sum() < 3:
        return float("nan"), float("nan")
    w = np.sqrt(counts[sel]) / g[sel]  # 1 / (relative Poisson error of each bin's g)
    coef, cov = np.polyfit(r[sel] - sigma, g[sel], 1, w=w, cov="unscaled")
    return float(coef[1]), float(math.sqrt(cov[1, 1]))


def contacts_started(frames):
    """Pair contacts (distance < r_i + r_j) that begin between consecutive frames (one per step).

    Returns (started, elapsed time)."""
    started, previous, first, last = 0, None, None, None
    for f in frames:
        first = first if first is not None else f["t"]
        last = f["t"]
        i, j = soft_spheres.contacts(f["pos"], f["radius"], f["lo"], f["hi"])[:2]
        key = i.astype(np.int64) * len(f["ids"]) + j  # i < j
        if previous is not None:
            started += len(np.setdiff1d(key, previous, assume_unique=True))
        previous = key
    return started, last - first


def kinetic_energy(frame, mass):
    return 0.5 * float((mass * (frame["vel"] ** 2).sum(axis=1)).sum())
