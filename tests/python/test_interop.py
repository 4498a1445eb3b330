"""Interop: LAMMPS data and dump files read by MDAnalysis, a g(r) and an MSD from the arrays,
and the picture."""
import numpy as np
import pytest

import hardsphere as hs


@pytest.fixture(scope="module")
def sim():
    s = hs.Stepper(hs.System.random(n=400, phi=0.2, seed=8))
    s.run(steps=50)
    return s


def test_mdanalysis_reads_data_and_dump(sim, tmp_path):
    mda = pytest.importorskip("MDAnalysis")
    data, dump = str(tmp_path / "s.data"), str(tmp_path / "s.dump")
    sim.write_data(data)
    sim.write_dump(dump)
    u = mda.Universe(data, atom_style="id type diameter density x y z")
    order = np.argsort(u.atoms.ids)
    assert np.array_equal(u.atoms.ids[order], sim.ids)
    assert np.allclose(u.atoms.positions[order], sim.positions, rtol=0, atol=1e-4)  # MDAnalysis keeps float32
    assert np.allclose(u.dimensions[:3], sim.box.lengths)
    d = mda.Universe(data, dump, format="LAMMPSDUMP", atom_style="id type diameter density x y z")
    assert len(d.trajectory) == 1
    order = np.argsort(d.atoms.ids)
    assert np.allclose(d.atoms.positions[order], sim.positions, rtol=0, atol=1e-4)


def g_of_r(positions, lengths, r_max, bins):
    """Radial distribution function over all pairs, minimum image (periodic box)."""
    L = np.asarray(lengths)
    d = positions[:, None, :] - positions[None, :, :]
    d -= L * np.round(d / L)
    r = np.sqrt((d ** 2).sum(-1))[np.triu_indices(len(positions), 1)]
    counts, edges = np.histogram(r, bins=bins, range=(0, r_max))
    shell = 4 / 3 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    density = len(positions) / np.prod(L)
    return edges, counts / (shell * density * len(positions) / 2)


def test_g_of_r_from_arrays(sim):
    edges, g = g_of_r(sim.positions, sim.box.lengths, 4.0, 40)
    centres = (edges[1:] + edges[:-1]) / 2
    assert np.all(g[centres < 0.95] == 0)  # no pair closer than a diameter
    # Over 20 seeds the contact bin had mean 1.605 and sd 0.107 (the peak of a gas at 0.2; its
    # lower 4-sd edge 1.18), the mean beyond 3 diameters was 1 - 0.0024 with sd 0.0036.
    assert g[(centres > 1.0) & (centres < 1.1)].max() > 1.17
    assert abs(g[centres > 3].mean() - 1) < 0.1


def test_msd_from_unwrapped_positions():
    sim = hs.EventEngine(hs.System.random(n=300, phi=0.1, seed=4))
    start = sim.unwrapped_positions
    msd = []
    sim.run(time=4.0, callback=lambda s: msd.append(((s.unwrapped_positions - start) ** 2).sum(1).mean()), every=0.5)
    assert len(msd) == 8 and all(b > a for a, b in zip(msd, msd[1:]))
    # Unwrapped displacements exceed half the box, which wrapped ones cannot.
    assert np.abs(sim.unwrapped_positions - start).max() > sim.box.lengths[0] / 2 or msd[-1] > 1


@pytest.mark.parametrize("color", ["type", "speed"])
def test_render_writes_png(sim, tmp_path, color):
    path = tmp_path / f"{color}.png"
    assert hs.render(sim, str(path), color=color, size=3, dpi=60) == str(path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="must be 'type' or 'speed'"):
        hs.render(sim, str(path), color="mass")
