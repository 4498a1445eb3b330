"""compare.lammps_files: data files as hardsphere and LAMMPS write them, text dumps with any column
set, and the thermo and loop-time lines of a log. The files written by LAMMPS come from Debian's
`lmp` (skipped without it), those of hardsphere from the built program."""
import math
import shutil
import subprocess

import numpy as np
import pytest

from compare import lammps_files as lf

SPHERE_DATA = """LAMMPS data file via write_data, version 29 Sep 2021, timestep = 10

3 atoms
2 atom types
1 bonds
1 bond types

0 10 xlo xhi
-1 9 ylo yhi
0 12.5 zlo zhi
1.5 0 -0.5 xy xz yz

Pair Coeffs # hardsphere

1 1
2 1.4

Atoms # sphere

7 2 1.4 0.5 1.0 2.0 3.0 0 1 -2
3 1 1 1.9098593171027443 4 5 6 1 0 0
5 1 0 2.5 7 8 9 0 0 0

Velocities

5 0.5 0.6 0.7 0 0 0
3 0.1 0.2 0.3 0 0 0
7 -1 -2 -3 0.25 0 -0.25

Bonds

1 1 3 5
"""


def test_reads_header_box_tilt_and_sections(tmp_path):
    (tmp_path / "a.data").write_text(SPHERE_DATA)
    d = lf.read_data(tmp_path / "a.data")
    assert d.title.startswith("LAMMPS data file") and len(d) == 3 and d.ntypes == 2
    assert d.counts == {"atoms": 3, "atom types": 2, "bonds": 1, "bond types": 1}
    assert d.box.tolist() == [[0, 10], [-1, 9], [0, 12.5]] and d.tilt.tolist() == [1.5, 0, -0.5]
    assert d.ids.tolist() == [3, 5, 7] and d.types.tolist() == [1, 1, 2]  # sorted by id
    assert d.pos.tolist() == [[4, 5, 6], [7, 8, 9], [1, 2, 3]]
    assert d.image.tolist() == [[1, 0, 0], [0, 0, 0], [0, 1, -2]] and d.image.dtype.kind == "i"
    assert d.vel.tolist() == [[0.1, 0.2, 0.3], [0.5, 0.6, 0.7], [-1, -2, -3]]
    assert d.omega.tolist() == [[0, 0, 0], [0, 0, 0], [0.25, 0, -0.25]]  # wx wy wz kept
    assert d.radius.tolist() == [0.5, 0.0, 0.7]
    # mass = density x volume; a point particle (diameter 0) has its mass in the density column
    assert d.mass == pytest.approx([1.0, 2.5, 0.5 * math.pi / 6 * 1.4 ** 3], rel=1e-15)
    assert d.lengths.tolist() == [10, 10, 12.5] and d.volume == 1250.0
    # images with a tilted box: a y image moves x by xy, a z image x by xz and y by yz
    assert d.unwrapped()[2].tolist() == [1.0 + 1.5, 2.0 + 10 + 2 * 0.5, 3.0 - 25.0]


def test_optional_columns_and_sections(tmp_path):
    text = ("no images, no angular velocities\n\n2 atoms\n\n0 4 xlo xhi\n0 4 ylo yhi\n0 4 zlo zhi\n\n"
            "Atoms\n\n1 1 1 1 1 1 1\n2 1 1 1 3 3 3\n\nVelocities\n\n1 1 0 0\n2 -1 0 0\n")
    (tmp_path / "b.data").write_text(text)
    d = lf.read_data(tmp_path / "b.data")
    assert d.image is None and d.omega is None and d.tilt is None and d.ntypes == 1
    assert d.unwrapped().tolist() == d.pos.tolist() == [[1, 1, 1], [3, 3, 3]]
    (tmp_path / "c.data").write_text(text.split("Velocities")[0])  # no Velocities: at rest
    assert lf.read_data(tmp_path / "c.data").vel.tolist() == [[0, 0, 0]] * 2


@pytest.mark.parametrize("edit", [
    lambda t: t.replace("Atoms # sphere", "Atoms # atomic"),       # another atom style
    lambda t: t.replace("5 1 0 2.5 7 8 9 0 0 0\n", ""),            # a row short
    lambda t: t.replace("5 1 0 2.5 7 8 9 0 0 0", "5 1 0 2.5 7 8 9"),  # image flags on some rows only
    lambda t: t.replace("5 0.5 0.6 0.7", "4 0.5 0.6 0.7"),         # a velocity for an unknown id
    lambda t: t.replace("Bonds", "Atoms # sphere"),                # a second Atoms section
])
def test_bad_files_are_refused(tmp_path, edit):
    (tmp_path / "bad.data").write_text(edit(SPHERE_DATA))
    with pytest.raises(ValueError):
        lf.read_data(tmp_path / "bad.data")


def test_write_then_read_is_exact(tmp_path):
    rng = np.random.default_rng(4)
    pos = rng.uniform(0, 7, (20, 3))
    data = lf.spheres(pos, rng.normal(size=(20, 3)), box=((0.1, 7.1), (0, 7), (-3, 4)), diameter=rng.uniform(0.5, 1.5, 20),
                      mass=rng.uniform(1, 2, 20), types=rng.integers(1, 4, 20), image=rng.integers(-3, 3, (20, 3)),
                      omega=rng.normal(size=(20, 3)), tilt=(0.5, -0.25, 1.0), title="random spheres")
    data.masses = {1: 1.0, 2: 2.0, 3: 3.0}
    lf.write_data(tmp_path / "r.data", data)
    back = lf.read_data(tmp_path / "r.data")
    for field in ("box", "tilt", "ids", "types", "diameter", "density", "pos", "vel", "image", "omega"):
        assert np.array_equal(getattr(back, field), getattr(data, field)), field
    assert back.title == "random spheres" and back.masses == data.masses and back.ntypes == 3
    assert back.mass == pytest.approx(data.mass, rel=1e-15)
    lf.write_data(tmp_path / "again.data", back)
    assert (tmp_path / "again.data").read_text() == (tmp_path / "r.data").read_text()


def test_spheres_from_rows_defaults():
    d = lf.spheres_from_rows([(1, 2, 3, 0.5, 0, 0), (4, 5, 6, 0, 0, 0, 2.0), (7, 8, 9, 0, 0, 0, 1.0, 3.0)],
                             box=((0, 10),) * 3)
    assert d.ids.tolist() == [1, 2, 3] and d.diameter.tolist() == [1.0, 2.0, 1.0]
    # density 6/pi unless given: unit mass for a unit sphere, 8 for one of diameter 2
    assert d.mass == pytest.approx([1.0, 8.0, 3.0 * math.pi / 6], rel=1e-15)
    assert d.image is None and d.omega is None


def test_reads_what_hardsphere_writes(hs, tmp_path):
    p = subprocess.run([hs, "run", "--n", "50", "--phi", "0.2", "--steps", "30", "--boundary", "p,p,w", "--write-data",
                        "s.data", "--dump", "s.dump", "--dump-every", "10", "--json", "-"], cwd=tmp_path,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    d = lf.read_data(tmp_path / "s.data")
    assert len(d) == 50 and d.counts == {"atoms": 50, "atom types": 1} and d.tilt is None
    assert d.image is not None and d.omega is not None and not d.omega.any()  # hardsphere writes wx wy wz = 0
    assert d.mass == pytest.approx(np.ones(50), rel=1e-15) and np.all(d.radius == 0.5)
    lf.write_data(tmp_path / "copy.data", d)  # the program reads the copy and continues the same way
    runs = [subprocess.run([hs, "run", "--read-data", f, "--boundary", "p,p,w", "--steps", "50", "--json", "-"],
                           cwd=tmp_path, capture_output=True, text=True) for f in ("s.data", "copy.data")]
    assert runs[0].returncode == runs[1].returncode == 0
    assert '"collisions"' in runs[0].stdout
    assert [ln for ln in runs[0].stdout.splitlines() if "collisions" in ln] == \
        [ln for ln in runs[1].stdout.splitlines() if "collisions" in ln]
    frames = lf.read_dump_frames(tmp_path / "s.dump")
    assert [f.timestep for f in frames] == [0, 10, 20, 30] and frames[-1].bounds == "pp pp ff"
    last = frames[-1]
    assert last.names == ["id", "type", "radius", "x", "y", "z", "vx", "vy", "vz", "ix", "iy", "iz"]
    assert last.natoms == 50 and last.unwrapped and last["ix"].dtype.kind == "i"
    assert np.allclose(last.positions(), d.unwrapped(), rtol=0, atol=1e-12)  # the dump's last frame is the state


LAMMPS_STATE = """units lj
atom_style sphere
boundary p p p
region box prism 0 6 0 6 0 6 1.0 0.5 -0.5
create_box 2 box
create_atoms 1 random 20 4821 NULL
set type 1 type/fraction 2 0.5 77
set type 1 diameter 1.0
set type 2 diameter 0.6
set type 2 density 2.0
velocity all create 1.0 3049 dist gaussian mom yes
set atom 1 omega 0.5 -0.25 0.125
set atom 2 image 1 -1 2
compute ke all ke/atom
dump d all custom 1 state.dump id type mass radius x y z xu yu zu ix iy iz vx vy vz omegax c_ke
dump_modify d time yes units yes
thermo_style custom step ke
run 0
undump d
write_data state.data
run 0
"""


def test_reads_what_lammps_writes(tmp_path):
    lmp = shutil.which("lmp")
    if lmp is None:
        pytest.skip("Debian's lmp not on PATH")
    (tmp_path / "in.state").write_text(LAMMPS_STATE)
    p = subprocess.run([lmp, "-in", "in.state", "-log", "log.lammps", "-echo", "none"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr
    d = lf.read_data(tmp_path / "state.data")
    assert len(d) == 20 and d.counts["atoms"] == 20 and d.ntypes == 2 and d.tilt.tolist() == [1.0, 0.5, -0.5]
    assert d.box.tolist() == [[0, 6]] * 3 and d.image is not None and d.omega is not None
    assert d.omega[0].tolist() == [0.5, -0.25, 0.125] and d.image[1].tolist() == [1, -1, 2]
    assert set(np.round(d.diameter, 12).tolist()) == {1.0, 0.6}
    frames = lf.read_dump_frames(tmp_path / "state.dump")
    assert len(frames) == 1
    f = frames[0]
    assert f.time == 0.0 and f.units == "lj" and f.bounds == "pp pp pp"
    assert np.allclose(f.box, d.box, rtol=0, atol=1e-12) and np.allclose(f.tilt, d.tilt, rtol=0, atol=1e-12)
    assert f["id"].tolist() == d.ids.tolist() and f["type"].tolist() == d.types.tolist()
    assert np.allclose(f["radius"], d.radius) and np.allclose(f["mass"], d.mass, rtol=1e-5)
    assert np.allclose(f.table(["x", "y", "z"]), d.pos, rtol=0, atol=1e-4)  # the dump writes %g
    assert np.allclose(f.positions(), d.unwrapped(), rtol=0, atol=1e-4)  # xu yu zu: the images counted
    assert np.allclose(f["omegax"], d.omega[:, 0], rtol=1e-5) and len(f["c_ke"]) == 20
    lf.write_dump(tmp_path / "copy.dump", frames)  # a triclinic frame round-trips
    (g,) = lf.read_dump_frames(tmp_path / "copy.dump")
    assert np.array_equal(g.box, f.box) and np.array_equal(g.tilt, f.tilt) and g.names == f.names
    assert all(np.array_equal(g[c], f[c]) for c in f.names) and g.time == f.time and g.units == f.units
    log = (tmp_path / "log.lammps").read_text()
    blocks = lf.thermo_blocks(log)
    assert len(blocks) == 2 and all(len(b) == 1 and b[0]["Step"] == 0 and "KinEng" in b[0] for b in blocks)
    assert lf.thermo_rows(log) == blocks[-1]
    assert [(p, n) for _, p, n in lf.loop_times(log)] == [(1, 0), (1, 0)]


DUMP = ("ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n"
        "0 10\n-1 9.5\n0 1.25e+01\nITEM: ATOMS id type radius xu yu zu\n"
        "7 2 0.7 1.5 2 3 \n3 1 0.5 -1 2.5 3e-1 \n"
        "ITEM: TIMESTEP\n6\nITEM: NUMBER OF ATOMS\n0\nITEM: BOX BOUNDS pp pp pp\n"
        "0 10\n-1 9.5\n0 12.5\nITEM: ATOMS id type radius xu yu zu\n")


def test_read_dump(tmp_path):
    (tmp_path / "a.dump").write_text(DUMP)
    frames = list(lf.read_dump(tmp_path / "a.dump"))
    assert [f.timestep for f in frames] == [5, 6]
    f = frames[0]
    assert f["id"].tolist() == [3, 7] and f["type"].tolist() == [1, 2] and f["id"].dtype.kind == "i"
    assert f["xu"].tolist() == [-1.0, 1.5] and f["zu"].tolist() == [0.3, 3.0] and set(f) == set(f.names)
    assert f.box_lo.tolist() == [0, -1, 0] and f.box_hi.tolist() == [10, 9.5, 12.5] and f.tilt is None
    assert f.positions().tolist() == [[-1, 2.5, 0.3], [1.5, 2, 3]] and f.unwrapped
    assert frames[1].natoms == 0 and len(frames[1]["radius"]) == 0
    assert list(lf.read_dump(tmp_path / "a.dump", sort=False))[0]["id"].tolist() == [7, 3]  # the file's order
    (tmp_path / "b.dump").write_text(DUMP.replace("3 1 0.5 -1 2.5 3e-1 \n", ""))  # one atom row short
    with pytest.raises(ValueError):
        list(lf.read_dump(tmp_path / "b.dump"))
    (tmp_path / "c.dump").write_text(DUMP.replace("ITEM: NUMBER", "ITEM: NUMBERS", 1))
    with pytest.raises(ValueError):
        list(lf.read_dump(tmp_path / "c.dump"))


def test_dump_with_images_and_liggghts_items(tmp_path):
    text = ("ITEM: TIMESTEP\n3\nITEM: LABEL\nSIMULATION\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff pp pp\n"
            "0 4\n0 5\n0 6\nITEM: ATOMS id x y z ix iy iz\n1 1 1 1 1 -1 2\n")
    (tmp_path / "i.dump").write_text(text)
    (f,) = lf.read_dump_frames(tmp_path / "i.dump")
    assert f.bounds == "ff pp pp" and f.positions().tolist() == [[5, -4, 13]] and f.unwrapped
    lf.write_dump(tmp_path / "again.dump", [f])
    (g,) = lf.read_dump_frames(tmp_path / "again.dump")
    assert g.positions().tolist() == f.positions().tolist() and g.bounds == f.bounds


def test_thermo_blocks_and_loop_times():
    log = ("Step KinEng f_hs[1] \n0 1.5 0 \n10 1.5 12 \nLoop time of 0.00389111 on 2 procs for 100 steps with 500 "
           "atoms, finish time Tue Nov 24 2026\n\nWARNING: something\n   Step Temp \n 10 1.0\n20 1.1\n"
           "Loop time of 6.48e-2 on 1 procs for 400 steps with 500 atoms\n")
    blocks = lf.thermo_blocks(log)
    assert blocks == [[{"Step": 0, "KinEng": 1.5, "f_hs[1]": 0}, {"Step": 10, "KinEng": 1.5, "f_hs[1]": 12}],
                      [{"Step": 10, "Temp": 1.0}, {"Step": 20, "Temp": 1.1}]]
    assert lf.thermo_rows(log) == blocks[1] and lf.thermo_rows("nothing") == []
    assert lf.loop_times(log) == [(0.00389111, 2, 100), (0.0648, 1, 400)]
    assert lf.loop_times("nothing") == []
