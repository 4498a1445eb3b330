"""The owned + ghost path on LAMMPS's other decompositions: slabs thinner than the ghost shell
(LAMMPS relays ghosts through two swaps), 2-d and 3-d grids (corner ghosts come via a neighbour's
neighbour), tiled sub-domains from recursive bisection (static, and re-cut during the run), walls on
a split axis, two sphere sizes. Every grid must give the standalone stepper's collisions and final
state, keep the energy, and need no step re-run for all atoms: a relay that carried a wrong owner
velocity would show up as re-runs. Ranks may exceed the cores (oversubscribed); 1000 spheres keep
each run under a second. The rank count comes from the grid (--np is not used).
Groups: periodic, walls, two_sizes."""
import numpy as np

from tests.lammps.lammps_runner import Cases, main, read_data
from compare.lammps_files import write_data

cases = Cases(__file__)


def scene(ctx, name):
    """The scene's data file, the standalone's run of it (to sa_NAME.data) and its settings."""
    if name == "walls":
        data = ctx.state("walls.data", "--n", 1000, "--phi", 0.3, "--boundary", "p,p,w")
    else:
        data = ctx.state("periodic.data", "--n", 1000, "--phi", 0.3)
    if name == "two_sizes":  # every third sphere shrunk to diameter 0.6 (same density, so lighter): no overlaps
        state = read_data(ctx.path(data))
        state.diameter[state.ids % 3 == 0] = 0.6
        data = write_data(ctx.path("two_sizes.data"), state)
    opts = ["--boundary", "p,p,w"] if name == "walls" else []
    # Positions differ from the standalone's by round-off that chaos grows ~100-fold per 50 steps,
    # faster with the light small spheres: they run 100 steps, the others 200.
    steps = 100 if name == "two_sizes" else 200
    ref = ctx.standalone("--read-data", data, *opts, "--steps", steps, "--dt", 0.01, "--write-data", f"sa_{name}.data")
    return data, ref, steps


@cases.case
def grid(ctx, case):
    """One layout: 'processors P Q R' on P Q R ranks, or 'rcb N': comm_style tiled, sub-domains cut
    by recursive bisection (balance rcb) on N ranks, again every 20 steps on the walls scene
    (fix balance)."""
    name, layout = case["scene"], case["grid"]
    data, ref, steps = scene(ctx, name)
    walls, rcb = name == "walls", layout.startswith("rcb")
    ranks = int(layout.split()[1]) if rcb else int(np.prod([int(t) for t in layout.split()]))
    balance = ("fix bal all balance 20 1.0 rcb" if walls else "balance 1.0 rcb") if rcb else ""
    rows = ctx.lammps("decompositions/grid.lmp", pre=("comm_style tiled" if rcb else f"processors {layout}") + "\n",
                      vars=dict(data=data, boundary="p p f" if walls else "p p p", balance=balance, steps=steps,
                                out="lmp.data"), np=ranks).rows
    dx, dv = ctx.difference(f"sa_{name}.data", "lmp.data", (True, True, not walls))
    return {"collisions": rows[-1]["f_hs[1]"], "wall bounces": rows[-1]["f_hs[5]"], "steps re-run": rows[-1]["f_hs[6]"],
            "kinetic energy": rows[-1]["KinEng"], "max |dx|": dx, "max |dv|": dv}, dict(standalone=ref, start=rows[0])


if __name__ == "__main__":
    raise SystemExit(main(cases))
