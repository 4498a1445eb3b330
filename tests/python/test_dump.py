"""hs.DumpWriter: the CLI's multi-frame --dump from Python, byte for byte, committed only on close."""
import os

import numpy as np
import pytest

import hardsphere as hs
from compare.lammps_files import read_dump_frames


@pytest.fixture(scope="module")
def gas_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("dump") / "gas.data"
    hs.System.random(n=300, phi=0.25, seed=11).write_data(str(path))
    return str(path)


def test_stepper_frames_equal_cli(cli, gas_file, tmp_path):
    """--dump-every 50 over 200 steps is a frame at 0 and one every 50 steps: the same file."""
    cli("run", "--read-data", gas_file, "--steps", 200, "--dump", tmp_path / "cli.dump", "--dump-every", 50)
    sim = hs.Stepper(hs.System.from_data(gas_file))
    with hs.DumpWriter(str(tmp_path / "py.dump")) as dump:
        dump.write(sim)
        sim.run(steps=200, callback=dump.write, every=50)
        assert dump.frames == 5 and not os.path.exists(tmp_path / "py.dump")  # a temporary until closed
    assert dump.closed
    assert (tmp_path / "py.dump").read_bytes() == (tmp_path / "cli.dump").read_bytes()
    frames = read_dump_frames(str(tmp_path / "py.dump"))
    assert [f.timestep for f in frames] == [0, 50, 100, 150, 200]
    assert np.array_equal(frames[-1]["id"], sim.ids)
    assert np.allclose(frames[-1].positions(), sim.unwrapped_positions, rtol=0, atol=1e-4)


def test_event_engine_frames_per_block(cli, gas_file, tmp_path):
    """The CLI writes a frame after each block; a callback every block does the same."""
    cli("run", "--read-data", gas_file, "--engine", "event", "--time", 1.0, "--blocks", 4,
        "--dump", tmp_path / "cli.dump")
    sim = hs.EventEngine(hs.System.from_data(gas_file))
    dump = hs.DumpWriter(str(tmp_path / "py.dump"))
    dump.write(sim)
    sim.run(time=1.0, blocks=4, callback=dump.write, every=0.25)
    dump.close()
    cli_frames = read_dump_frames(str(tmp_path / "cli.dump"))
    py_frames = read_dump_frames(str(tmp_path / "py.dump"))
    assert len(py_frames) == len(cli_frames) == 5
    for a, b in zip(py_frames, cli_frames):
        assert a.timestep == b.timestep
        assert a.names == b.names and all(np.array_equal(a[c], b[c]) for c in a.names)


def test_discarded_or_failed_dump_leaves_nothing(tmp_path):
    sim = hs.Stepper(hs.System.random(n=100, phi=0.1, seed=1))
    with pytest.raises(RuntimeError):
        with hs.DumpWriter(str(tmp_path / "x.dump")) as dump:
            dump.write(sim)
            raise RuntimeError("stop")
    d = hs.DumpWriter(str(tmp_path / "y.dump"))
    d.write(sim)
    d.discard()
    assert os.listdir(tmp_path) == []
    with pytest.raises(ValueError, match="is closed"):
        d.write(sim)
    with pytest.raises(OSError):
        hs.DumpWriter(str(tmp_path))  # a directory
    w = hs.DumpWriter(str(tmp_path / "w.dump"))
    with pytest.raises(TypeError):
        w.write(sim.system())  # not an engine
    w.discard()
    d = hs.DumpWriter(str(tmp_path / "z.dump"))
    d.close()
    d.close()  # twice: nothing more
    assert os.listdir(tmp_path) == ["z.dump"] and (tmp_path / "z.dump").read_bytes() == b""


def test_mdanalysis_reads_frames(tmp_path):
    mda = pytest.importorskip("MDAnalysis")
    sim = hs.Stepper(hs.System.random(n=200, phi=0.2, seed=2))
    sim.write_data(str(tmp_path / "s.data"))
    with hs.DumpWriter(str(tmp_path / "s.dump")) as dump:
        dump.write(sim)
        sim.run(steps=30, callback=dump.write, every=10)
    u = mda.Universe(str(tmp_path / "s.data"), str(tmp_path / "s.dump"), format="LAMMPSDUMP",
                     atom_style="id type diameter density x y z")
    assert len(u.trajectory) == 4 and len(u.atoms) == 200
