"""The tracker (--track ID --track-every T --track-file FILE) in both engines: one row per
sample at exact times, unwrapped positions continuous across periodic faces, pair-collision
counts that only grow, and the output contract (refusals with status 2 before any file exists,
the file committed with the run's other outputs)."""
import json
import os

import numpy as np
import pytest

from hs_run import run

ENGINES = {"stepper": ["--dt", 0.01], "event": ["--engine", "event"]}


def read_track(path):
    lines = path.read_text().splitlines()
    header = [l for l in lines if l.startswith("#")]
    rows = np.loadtxt(path, comments="#", ndmin=2)
    return header, rows


@pytest.mark.parametrize("engine", ENGINES)
def test_rows_at_each_interval(hs, tmp_path, engine):
    p = run(hs, "--n", 300, "--phi", 0.2, "--time", 4, *ENGINES[engine], "--track", 7, "--track-every", 0.25,
            "--track-file", "t.txt", "--json", "s.json", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    header, rows = read_track(tmp_path / "t.txt")
    assert header[-1] == "# time x y z vx vy vz pair_collisions" and "sphere id 7" in header[0]
    assert rows.shape == (17, 8)
    np.testing.assert_allclose(rows[:, 0], 0.25 * np.arange(17), rtol=0, atol=1e-12)
    counts = rows[:, 7]
    assert counts[0] == 0 and np.all(np.diff(counts) >= 0) and counts[-1] > 0
    summary = json.loads((tmp_path / "s.json").read_text())
    assert summary["track"] == {"id": 7, "every": 0.25, "samples": 17, "file": "t.txt"}
    assert sorted(os.listdir(tmp_path)) == ["s.json", "t.txt"]  # no temporaries left


def test_engines_write_the_same_track(hs, tmp_path):
    tracks = []
    for engine in ENGINES:
        p = run(hs, "--n", 300, "--phi", 0.2, "--time", 2, *ENGINES[engine], "--track", 11, "--track-every", 0.5,
                "--track-file", f"{engine}.txt", cwd=tmp_path)
        assert p.returncode == 0, p.stderr
        tracks.append(read_track(tmp_path / f"{engine}.txt")[1])
    np.testing.assert_array_equal(tracks[0][:, 7], tracks[1][:, 7])
    np.testing.assert_allclose(tracks[0][:, 1:7], tracks[1][:, 1:7], atol=1e-6)


def write_two_spheres(path, length=6.0):
    """Sphere 1 flies along +x through the periodic faces; sphere 2 flies parallel, out of its way."""
    path.write_text(f"""two spheres

2 atoms
1 atom types

0 {length} xlo xhi
0 {length} ylo yhi
0 {length} zlo zhi

Atoms # sphere

1 1 1.0 1.909859317102744 5.5 1.0 1.0
2 1 1.0 1.909859317102744 1.0 4.0 4.0

Velocities

1 1.25 0 0
2 1.25 0 0
""")


@pytest.mark.parametrize("engine", ENGINES)
def test_unwrapped_position_is_continuous_across_periodic_faces(hs, tmp_path, engine):
    write_two_spheres(tmp_path / "two.data")
    p = run(hs, "--read-data", "two.data", "--time", 20, *ENGINES[engine], "--track", 1, "--track-every", 0.5,
            "--track-file", "t.txt", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    rows = read_track(tmp_path / "t.txt")[1]
    # x crosses the face at 6 four times; unwrapped it is the straight flight x0 + v t.
    np.testing.assert_allclose(rows[:, 1], 5.5 + 1.25 * rows[:, 0], rtol=0, atol=1e-9)
    assert rows[-1, 1] > 4 * 6.0
    np.testing.assert_allclose(rows[:, 2:4], 1.0, atol=1e-12)
    assert np.all(rows[:, 7] == 0)


@pytest.mark.parametrize("args,needle", [
    (["--dt", 0.01, "--time", 1, "--track", 1, "--track-every", 0.015], "--track-every 0.015 is not a whole number"),
    (["--dt", 0.01, "--time", 1, "--track", 1, "--track-every", 0.004], "is not a whole number of steps"),
    (["--engine", "event", "--time", 1, "--track", 99, "--track-every", 0.1], "--track 99: no sphere has this id"),
    (["--time", 1, "--track", 99, "--track-every", 0.1], "--track 99: no sphere has this id"),
    (["--engine", "event", "--time", 1, "--track", 1, "--track-every", 0], "--track-every 0 must be positive"),
    (["--engine", "event", "--time", 1, "--track", 1, "--track-every", "nan"], "--track-every nan"),
    (["--engine", "event", "--time", 1, "--track", "x", "--track-every", 1], "--track 'x' is not a whole number"),
    (["--engine", "event", "--time", 1e6, "--track", 1, "--track-every", 1e-6], "more than the limit"),
])
def test_bad_tracker_values_are_refused(hs, tmp_path, args, needle):
    p = run(hs, "--n", 20, "--phi", 0.1, *args, "--track-file", "t.txt", "--json", "s.json", cwd=tmp_path)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert p.stderr.startswith("hardsphere: error:") and needle in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("missing", ["--track", "--track-every", "--track-file"])
def test_tracker_options_go_together(hs, tmp_path, missing):
    given = {"--track": 1, "--track-every": 0.1, "--track-file": "t.txt"}
    del given[missing]
    args = [x for kv in given.items() for x in kv]
    p = run(hs, "--n", 20, "--phi", 0.1, "--steps", 10, *args, cwd=tmp_path)
    assert p.returncode == 2 and "go together" in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("other", ["--json", "--dump", "--write-data"])
def test_track_file_on_another_output_is_refused(hs, tmp_path, other):
    p = run(hs, "--n", 20, "--phi", 0.1, "--steps", 10, "--track", 1, "--track-every", 0.1, "--track-file", "x",
            other, "./x", cwd=tmp_path)
    assert p.returncode == 2 and "same file" in p.stderr and "--track-file" in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []
