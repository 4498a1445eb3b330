"""The figures of compare.brownian: the heavy sphere's path, its MSD and velocity autocorrelation,
and the sweep over density and size."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_path(rows, path, title):
    fig = plt.figure(figsize=(14, 4.8), constrained_layout=True)
    t = rows[:, 0]
    ax3 = fig.add_subplot(1, 3, 1, projection="3d")
    ax3.scatter(rows[:, 1], rows[:, 2], rows[:, 3], c=t, s=0.8, cmap="viridis")
    ax3.set_xlabel("x")
    ax3.set_ylabel("y")
    ax3.set_zlabel("z")
    axes = [fig.add_subplot(1, 3, 2), fig.add_subplot(1, 3, 3)]
    for ax, (a, b) in zip(axes, [(1, 2), (1, 3)]):
        sc = ax.scatter(rows[:, a], rows[:, b], c=t, s=1.5, cmap="viridis")
        ax.set_xlabel("x (unwrapped)")
        ax.set_ylabel("yz"[b - 2] + " (unwrapped)")
        ax.set_aspect("equal", adjustable="datalim")
    fig.colorbar(sc, ax=axes, label="time")
    fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_msd_vacf(results, path, m_big):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.4))
    colors = {"event": "tab:red", "stepper": "tab:blue"}
    for eng, res in results.items():
        t, msd, tv, acf, _ = res["curves"]
        a1.loglog(t, msd, "o", ms=3, color=colors[eng], label=f"{eng}")
        a2.plot(tv, acf, "-", color=colors[eng], label=f"{eng}")
    res = next(iter(results.values()))["result"]
    t = np.asarray(next(iter(results.values()))["curves"][0])
    a1.loglog(t, 3 * res["T_big_expected"] / m_big * t**2, "k--", lw=1,
              label="ballistic 3 kT (1 - M/M_tot) t^2 / M")
    a1.loglog(t, 6 * res["D"] * t, "k:", lw=1, label="diffusive 6 D t (measured D)")
    a1.loglog(t, 6 * res["D_expected"] * t, color="0.6", lw=1, label="6 D_exp t (Enskog, closure-free)")
    a1.axvline(res["tau"], color="0.8", lw=0.8)
    a1.set_xlabel("time")
    a1.set_ylabel("mean-squared displacement of the big sphere")
    a1.legend(fontsize=7)
    tv = np.linspace(0, 6 * res["tau"], 200)
    a2.plot(tv, np.exp(-tv * res["kT"] / (m_big * res["D"])), "k--", lw=1, label="exp(-t/tau), tau = M D / kT")
    a2.axhline(0, color="0.8", lw=0.8)
    a2.set_xlabel("time")
    a2.set_ylabel("<V(0).V(t)> / <V^2>")
    a2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_sweep(points, path):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.4))
    sizes = sorted({p["D_big"] for p in points})
    for k, d in enumerate(sizes):
        ps = sorted((p for p in points if p["D_big"] == d), key=lambda p: p["phi"])
        phi = [p["phi"] for p in ps]
        col = f"C{k}"
        a1.errorbar(phi, [p["D"] for p in ps], yerr=[p["D_err"] for p in ps], fmt="o", color=col,
                    label=f"measured, D_big {d:g}, M {ps[0]['M']:g}")
        a1.plot(phi, [p["D_expected"] for p in ps], "--", color=col, label="Enskog (closure-free, x momentum factor)")
        a1.plot(phi, [p["D_stokes_einstein"] for p in ps], ":", color=col, label="slip Stokes-Einstein, finite box")
        a2.errorbar(phi, [p["D"] / p["D_expected"] for p in ps], yerr=[p["D_err"] / p["D_expected"] for p in ps],
                    fmt="o-", color=col, label=f"D / D_exp, D_big {d:g}")
        a2.plot(phi, [p["D_stokes_einstein"] / p["D_expected"] for p in ps], ":", color=col,
                label=f"D_SE / D_exp, D_big {d:g}")
    a1.set_yscale("log")
    a1.set_xlabel("packing fraction")
    a1.set_ylabel("diffusion coefficient of the big sphere")
    a1.legend(fontsize=6)
    a2.axhline(1, color="0.7", lw=0.8)
    a2.set_xlabel("packing fraction")
    a2.set_ylabel("D / Enskog (closure-free)")
    a2.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
