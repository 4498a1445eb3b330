"""A picture of a state: spheres as shaded discs in depth order (matplotlib, Agg backend)."""
import numpy as np


def render(obj, path, *, color="type", axis=2, size=6.0, dpi=150, cmap=None):
    """Writes a PNG of `obj` (a System, Stepper or EventEngine) seen along `axis` (0, 1, 2).

    Spheres are drawn far ones first, each as a disc with a lighter highlight, coloured by
    `color`: "type" (tab10) or "speed" (viridis, with a colour bar). Returns the path.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import EllipseCollection

    pos, rad = obj.positions, obj.radii
    box = obj.box
    a, b = [d for d in range(3) if d != axis]
    order = np.argsort(pos[:, axis], kind="stable")  # far (low) first, near ones on top
    depth = (pos[order, axis] - box.lo[axis]) / box.lengths[axis]
    if color == "speed":
        values = np.linalg.norm(obj.velocities, axis=1)[order]
        cm = plt.get_cmap(cmap or "viridis")
        norm = matplotlib.colors.Normalize(values.min(), values.max() if values.max() > values.min() else values.min() + 1)
        base = cm(norm(values))[:, :3]
    elif color == "type":
        cm = plt.get_cmap(cmap or "tab10")
        base = cm((obj.types[order] - 1) % 10)[:, :3]
    else:
        raise ValueError(f"color '{color}' must be 'type' or 'speed'")
    shade = (0.45 + 0.55 * depth)[:, None]  # far spheres darker
    body = base * shade
    light = body + (1 - body) * 0.55

    la, lb = box.lengths[a], box.lengths[b]
    fig, ax = plt.subplots(figsize=(size, size * lb / la + (0.6 if color == "speed" else 0)))
    xy = np.column_stack([pos[order, a], pos[order, b]])
    d = 2 * rad[order]
    # Each disc is followed by its highlight, so a nearer sphere covers both.
    n = len(d)
    off = np.empty((2 * n, 2))
    off[0::2], off[1::2] = xy, xy + 0.25 * d[:, None] / 2 * np.array([-1, 1])
    widths = np.empty(2 * n)
    widths[0::2], widths[1::2] = d, 0.45 * d
    faces = np.ones((2 * n, 4))
    faces[0::2, :3], faces[1::2, :3], faces[1::2, 3] = body, light, 0.6
    edges = np.zeros((2 * n, 4))
    edges[0::2, 3] = 0.35
    ax.add_collection(EllipseCollection(widths, widths, 0, units="xy", offsets=off, transOffset=ax.transData,
                                        facecolors=faces, edgecolors=edges, linewidths=0.2))
    ax.set_xlim(box.lo[a], box.hi[a])
    ax.set_ylim(box.lo[b], box.hi[b])
    ax.set_aspect("equal")
    ax.set_xlabel("xyz"[a])
    ax.set_ylabel("xyz"[b])
    ax.set_title(f"{len(rad)} spheres, seen along {'xyz'[axis]}")
    if color == "speed":
        fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cm), ax=ax, label="speed",
                     orientation="horizontal", fraction=0.05, pad=0.1)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
