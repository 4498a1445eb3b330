"""The reports of compare.accuracy, written from their JSON rows (after a run, or again from the
committed JSON by `python3 -m compare.accuracy report --out DIR`): eos.md, speed.md, accuracy.md and
the two figures. Every number comes from the rows; a setting the rows do not hold is left out of the
text."""
import json
from pathlib import Path

# Smallenburg, "Efficient event-driven simulations of hard spheres", Eur. Phys. J. E 45, 22 (2022):
# CPU seconds per unit of simulated time of the published serial code at N = 8000, the figures the
# time-to-accuracy table compares with (literature values, not measured here).
PUBLISHED_EDMD = {0.3: 0.062, 0.45: 0.107}
PUBLISHED_NAME = "best published event-driven code (Smallenburg 2022)"

HEADER = ["phi", "engine", "precision", "detect", "dt", "dt/mean free time", "CPU s per unit time", "Z",
          "Z rel. error", "collision rate rel. error (= minus the deficit)", "energy drift", "KS distance",
          "max overlap"]


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def _setting(rows, key):
    """The rows' common value of a setting, or None (older JSON does not hold it)."""
    values = {r.get(key) for r in rows}
    return values.pop() if len(values) == 1 else None


# ----------------------------------------------------------------------------------------- eos
def eos_rows(data):
    return [[d["phi"], f"{d['z']:.4f} ± {d['z_err']:.4f}", f"{d['z_cs']:.4f}", f"{100 * (d['z'] / d['z_cs'] - 1):+.2f}%",
             f"{d['z_kolafa']:.4f}", f"{100 * (d['z'] / d['z_kolafa'] - 1):+.2f}%",
             f"{d['rate']:.4f} ± {d['rate_err']:.4f}", f"{d['rate_enskog_cs']:.4f}",
             f"{100 * (d['rate'] / d['rate_enskog_cs'] - 1):+.2f}%", f"{d['collisions']:.3g}"] for d in data]


def eos_markdown(data, generated=None):
    n, eq, blocks = _setting(data, "n"), _setting(data, "equilibrate"), _setting(data, "blocks")
    text = (f"Event engine, N = {n}" + (f", each state equilibrated for {eq} time units" if eq is not None else "")
            + ", then one run per packing fraction of the collisions in the last column"
            + (f", measured in {blocks} blocks" if blocks is not None else "")
            + " (error = standard error of the block means). Units: sigma = m = kT = 1. Carnahan-Starling Z_CS and "
            "Kolafa's Z_Kolafa, Enskog's collision rate with g_CS: compare.hard_sphere_theory.\n\n")
    head = "# Equation of state and collision rate of the event engine\n\n" + (generated + "\n\n" if generated else "")
    return head + text + md_table(["phi", "Z measured", "Z_CS", "vs CS", "Z_Kolafa", "vs Kolafa", "collision rate",
                                   "Enskog (g_CS)", "vs Enskog", "collisions"], eos_rows(data))


# --------------------------------------------------------------------------------------- speed
def speed_markdown(data, generated=None):
    phi = _setting(data, "phi")
    rows = [[d["n"], d["phi"], f"{d['collisions']:.3g}", f"{d['cpu']:.2f}", f"{d['collisions_per_second']:.3g}",
             f"{d['events_per_second']:.3g}"] for d in data]
    head = "# Speed of the event engine against N\n\n" + (generated + "\n\n" if generated else "")
    return head + (f"Event engine, packing fraction {phi}, one thread, equilibrated states, one run per N (CPU time "
                   "of the event loop only).\n\n" + md_table(["N", "phi", "collisions", "CPU s", "collisions/s",
                                                              "events/s"], rows))


# ------------------------------------------------------------------------------------ accuracy
def fmt_rows(rows):
    out = []
    for d in rows:
        out.append([d["phi"], d["engine"], d["precision"], d["detect"], "-" if d["dt"] is None else d["dt"],
                    "-" if d["dt"] is None else f"{d['mean_free_times_per_step']:.3f}",
                    f"{d['cpu_per_time']:.4g}", f"{d['z']:.4f}", f"{100 * d['z_rel_err']:+.2f}%",
                    f"{100 * d['rate_rel_err']:+.2f}%", f"{d['energy_rel_drift']:.1e}", f"{d['ks']:.4f}",
                    f"{d['max_overlap']:.1e}"])
    return out


def time_to_accuracy(rows, tol=0.01):
    """Per packing fraction the cheapest setting whose Z is within tol of the event engine's."""
    out = []
    for phi in sorted({d["phi"] for d in rows}):
        sub = [d for d in rows if d["phi"] == phi]
        ok = [d for d in sub if abs(d["z_rel_err"]) <= tol]
        best = min(ok, key=lambda d: d["cpu_per_time"])
        ev = [d for d in sub if d["engine"] == "event"][0]
        out.append(dict(phi=phi, n=best["n"], best=best, event=ev, published=PUBLISHED_EDMD.get(phi)))
    return out


def tta_markdown(tta_rows):
    tab = []
    for t in time_to_accuracy(tta_rows):
        b, e, pub = t["best"], t["event"], t["published"]
        tab.append([t["phi"], f"{b['engine']} {b['precision']} {b['detect']} dt={b['dt']}", f"{b['cpu_per_time']:.4g}",
                    f"{100 * b['z_rel_err']:+.2f}%", f"{e['cpu_per_time']:.4g}", f"{e['z']:.4f} ± {e['z_err']:.4f}",
                    "-" if pub is None or t["n"] != 8000 else f"{pub:g} ({pub / b['cpu_per_time']:.1f}x the stepper's)"])
    return md_table(["phi", "cheapest within 1%", "CPU s / unit time", "Z error", "event engine CPU s / unit time",
                     "precise Z (event)", PUBLISHED_NAME + ", N = 8000"], tab)


def accuracy_markdown(rows, tta_rows, generated=None):
    """accuracy.md: the density sweep and, with tta_rows, the time-to-accuracy table and its sweep."""
    n, t, eq, blocks = (_setting(rows, k) for k in ("n", "time", "equilibrate", "blocks"))
    text = (("# The stepper against the event engine: run time and error\n\n" + generated + "\n\n") if generated else "")
    text += (f"N = {n}" + (f", simulated time {t} per run" if t is not None else "")
             + (f" after {eq} units of event-driven equilibration" if eq is not None else "")
             + "; reference = event engine on the same state"
             + (f" (Z error bar from {blocks} blocks)" if blocks is not None else "") + ". "
             "The stepper's Z carries a statistical error of about the reference's error bar (same N and run length), "
             "so |Z error| below ~2x that bar is noise. The collision-rate error is also the estimate of missed (-) "
             "or spurious (+) collisions: 1 - rate/exact rate.\n\n" + md_table(HEADER, fmt_rows(rows)))
    if tta_rows:
        text += (f"\n### Time to accuracy (N = {tta_rows[0]['n']})\n\nCheapest setting whose Z is within 1% of the event "
                 "engine's Z on the same state (CPU seconds per unit of simulated time, one thread).\n\n")
        text += tta_markdown(tta_rows)
        text += "\nAll settings at this N:\n\n" + md_table(HEADER, fmt_rows(tta_rows))
    return text


def plot(rows, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    phis = sorted({d["phi"] for d in rows})
    fig, axes = plt.subplots(1, len(phis), figsize=(5 * len(phis), 4.2), squeeze=False)
    for ax, phi in zip(axes[0], phis):
        sub = [d for d in rows if d["phi"] == phi]
        ref = [d for d in sub if d["engine"] == "event"][0]
        floor = max(ref["z_err"] / ref["z"], 1e-5)
        keys = sorted({(d["precision"], d["detect"]) for d in sub if d["engine"] == "stepper"})
        for k in keys:
            c = sorted([d for d in sub if (d["precision"], d["detect"]) == k], key=lambda d: d["dt"])
            x = [d["cpu_per_time"] for d in c]
            y = [max(abs(d["z_rel_err"]), floor / 10) for d in c]
            line, = ax.loglog(x, y, "o-", lw=0.8, label=f"stepper {k[0]} {k[1]} (dt increasing along the line)")
            for d, xi, yi in zip(c, x, y):
                ax.annotate(f"{d['dt']:g}", (xi, yi), fontsize=6, color=line.get_color(), xytext=(2, 2),
                            textcoords="offset points")
        ax.loglog([ref["cpu_per_time"]], [floor], "k*", ms=12, label="event engine (plotted at its error bar)")
        ax.axhline(0.01, color="grey", ls=":", lw=1)
        ax.axhspan(floor / 10, 2 * floor, color="grey", alpha=0.15, lw=0, label="statistical noise (< 2 error bars)")
        ax.set_xlabel("CPU s per unit simulated time")
        ax.set_ylabel("|relative error of Z|")
        ax.set_title(f"{title}, phi = {phi}")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def split_sweeps(rows):
    """accuracy.json holds the density sweep and then the time-to-accuracy sweep: (sweep, tta) by N,
    the time-to-accuracy sweep being the last N (None when there is one N only)."""
    ns = list(dict.fromkeys(d["n"] for d in rows))
    if len(ns) == 1:
        return rows, None
    return [d for d in rows if d["n"] == ns[0]], [d for d in rows if d["n"] == ns[-1]]


def from_json(out, figures=True, write_accuracy=False):
    """Rewrites DIR/eos.md and DIR/speed.md (and with write_accuracy DIR/accuracy.md) from the JSON in
    DIR, and the two figures from accuracy.json; returns the files written."""
    out = Path(out)
    written = []
    for stem, writer in (("eos", eos_markdown), ("speed", speed_markdown)):
        if (out / f"{stem}.json").exists():
            (out / f"{stem}.md").write_text(writer(json.loads((out / f"{stem}.json").read_text())))
            written.append(out / f"{stem}.md")
    if (out / "accuracy.json").exists():
        rows, tta = split_sweeps(json.loads((out / "accuracy.json").read_text()))
        if write_accuracy:
            (out / "accuracy.md").write_text(accuracy_markdown(rows, tta))
            written.append(out / "accuracy.md")
        if figures:
            plot(rows, out / "accuracy.png", f"N = {rows[0]['n']}")
            written.append(out / "accuracy.png")
            if tta:
                plot(tta, out / "time_to_accuracy.png", f"N = {tta[0]['n']}")
                written.append(out / "time_to_accuracy.png")
    return written

