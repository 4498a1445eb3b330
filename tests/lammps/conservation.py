"""10^4 steps of 256 spheres: energy to 1e-10 relative, momentum to round-off, no overlap left."""
import numpy as np

from tests.lammps.lammps_runner import Cases, main, read_data

cases = Cases(__file__)


@cases.case
def long_run(ctx, case):
    ctx.state("init.data", "--n", 256, "--phi", 0.3)
    rows = ctx.lammps("conservation/long_run.lmp", vars=dict(data="init.data", out="lmp.data")).rows
    final = read_data(ctx.path("lmp.data"))
    dr = final.pos[:, None, :] - final.pos[None, :, :]
    dr -= final.lengths * np.round(dr / final.lengths)
    r = np.sqrt((dr ** 2).sum(-1)) + np.eye(len(final)) * 10
    return dict(collisions=rows[-1]["f_hs[1]"], kinetic_energy=rows[-1]["KinEng"],
                max_momentum=max(abs(r_[k]) for r_ in rows for k in ("v_px", "v_py", "v_pz")),
                min_distance=float(r.min())), dict(start=rows[0])


if __name__ == "__main__":
    raise SystemExit(main(cases))
