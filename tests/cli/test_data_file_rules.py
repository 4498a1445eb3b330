"""Data files through `hardsphere run --read-data`: each class of malformed file the reader used
to accept silently (or to end with an internal error) is refused with status 2 and file:line.
The reader's full rule set is tested in tests/unit/test_lammps_io.cpp.
"""
import pytest

from hs_run import run, run_json


def write_state(hs, path, *args):
    p = run(hs, "--n", 30, "--phi", 0.1, "--steps", 0, "--write-data", path, *args)
    assert p.returncode == 0, p.stderr
    return path.read_text().splitlines()


def line_of(lines, text):
    return next(i for i, l in enumerate(lines) if l.split("#")[0].strip() == text)


def edit(lines, index, new):
    out = list(lines)
    out[index] = new
    return out


def velocity_duplicate(lines):
    v = line_of(lines, "Velocities") + 2
    first_id = lines[v].split()[0]
    return edit(lines, v + 1, " ".join([first_id] + lines[v + 1].split()[1:])), v + 2, [f"atom id {first_id}", "twice"]


def image_flags(flags):
    def f(lines):
        a = line_of(lines, "Atoms") + 2
        return edit(lines, a, " ".join(lines[a].split()[:7] + flags)), a + 1, ["image flag", flags[0]]
    f.__name__ = "image_flags_" + "_".join(flags)
    return f


def repeated(header):
    def f(lines):
        at = line_of(lines, "Atoms")
        out = lines[:at] + [header] + lines[at:]
        return out, at + 1, ["appears twice"]
    f.__name__ = "repeated_" + header.split()[-1]
    return f


def short_masses(lines):
    at = line_of(lines, "Atoms")
    out = lines[:at] + ["Masses", "", "1 1.0", "2 1.0", ""] + lines[at:]  # the header says 1 atom type
    return out, at + 4, ["expected a section name", "'2 1.0'"]


def masses_missing_rows(lines):
    out = [l.replace("1 atom types", "3 atom types") for l in lines]
    at = line_of(out, "Atoms")
    out = out[:at] + ["Masses", "", "1 1.0", ""] + out[at:]
    return out, at + 5, ["Masses section ends after 1 of 3 atom types"]


def huge_count(lines):
    i = next(i for i, l in enumerate(lines) if l.endswith(" atoms"))
    return edit(lines, i, "99999999999999 atoms"), i + 1, ["atom count '99999999999999'", "134217728"]


def overlapping(lines):
    # The second atom moved onto the first: whole-state checks name the line too.
    a = line_of(lines, "Atoms") + 2
    first, second = lines[a].split(), lines[a + 1].split()
    return edit(lines, a + 1, " ".join(second[:4] + first[4:7] + second[7:])), a + 1, [f"overlaps atom {second[0]}"]


def coordinate_too_far(lines):
    a = line_of(lines, "Atoms") + 2
    w = lines[a].split()
    return edit(lines, a, " ".join(w[:4] + ["1e17"] + w[5:])), a + 1, ["x = 1e+17 cannot be resolved"]


@pytest.mark.parametrize("mutate", [
    velocity_duplicate,
    overlapping,
    coordinate_too_far,
    image_flags(["a", "b", "c"]),
    image_flags(["1e300", "-5", "7.5"]),
    repeated("30 atoms"),
    repeated("1 atom types"),
    repeated("0 10 xlo xhi"),
    short_masses,
    masses_missing_rows,
    huge_count,
], ids=lambda f: getattr(f, "__name__", "case"))
def test_malformed_data_files_are_refused_with_file_and_line(hs, tmp_path, mutate):
    lines = write_state(hs, tmp_path / "s.data")
    bad, line, needles = mutate(lines)
    (tmp_path / "bad.data").write_text("\n".join(bad) + "\n")
    p = run(hs, "--read-data", "bad.data", "--steps", 1, "--json", "out.json", cwd=tmp_path)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert p.stderr.startswith(f"hardsphere: error: bad.data:{line}: "), p.stderr
    for needle in needles:
        assert needle in p.stderr, (needle, p.stderr)
    assert not (tmp_path / "out.json").exists()


def test_subnormal_velocities_round_trip(hs, tmp_path):
    # strtod reports ERANGE for subnormals; the reader refused what the writer had written.
    write_state(hs, tmp_path / "s.data", "--init-speed", "1e-310")
    j = run_json(hs, "--read-data", tmp_path / "s.data", "--steps", 1)
    assert j["n"] == 30


def test_a_directory_is_not_a_data_file(hs, tmp_path):
    p = run(hs, "--read-data", tmp_path, "--steps", 1)
    assert p.returncode == 2 and "is a directory" in p.stderr, p.stderr


def two_spheres(tmp_path, distance):
    """Two unit spheres approaching head-on at `distance` in a periodic box of 10."""
    path = tmp_path / "pair.data"
    path.write_text("pair\n\n2 atoms\n1 atom types\n\n0 10 xlo xhi\n0 10 ylo yhi\n0 10 zlo zhi\n\nAtoms # sphere\n\n"
                    f"1 1 1 1.909859317102744 4 5 5\n2 1 1 1.909859317102744 {4 + distance!r} 5 5\n\n"
                    "Velocities\n\n1 1 0 0 0 0 0\n2 -1 0 0 0 0 0\n")
    return path


def test_overlap_within_float_rounding_is_read_by_float_runs_only(hs, tmp_path):
    # A float run may write pairs overlapping by its rounding (~16 eps_float L); reading its own
    # state back must work, and the pair, approaching, collides at once.
    path = two_spheres(tmp_path, 1 - 1e-6)
    j = run_json(hs, "--read-data", path, "--precision", "float", "--steps", 1, "--dt", 0.01)
    assert j["collisions"] == 1 and j["warnings"] == []
    for engine in ("stepper", "event"):  # double: refused, naming the float run's rounding as the likely cause
        p = run(hs, "--read-data", path, "--engine", engine, "--time", 0.01)
        assert p.returncode == 2 and "pair.data:12: atom 1 overlaps atom 2" in p.stderr
        assert "within a float run's rounding" in p.stderr and "--precision float" in p.stderr
    far = run(hs, "--read-data", two_spheres(tmp_path, 1 - 1e-3), "--precision", "float", "--steps", 1)
    assert far.returncode == 2 and "overlaps" in far.stderr and "within a float run's rounding" not in far.stderr



def bed_file(path, spheres):
    """Spheres of diameter 0.7 on the floor at z = 0.1 of a 5 x 5 x 10 box, walls along z."""
    rows = "".join(f"{i + 1} 1 0.7 1.9098593171027443 {x!r} {y!r} {z!r}\n" for i, (x, y, z) in enumerate(spheres))
    path.write_text(f"bed\n\n{len(spheres)} atoms\n1 atom types\n\n0 5 xlo xhi\n0 5 ylo yhi\n0.1 10.1 zlo zhi\n\n"
                    f"Atoms # sphere\n\n{rows}")
    return path


@pytest.mark.parametrize("engine", ["stepper", "event"])
def test_a_settled_bed_is_read_back_with_spheres_past_the_floor_by_rounding(hs, tmp_path, engine):
    # Positions near 0.45 are not exact in binary: the stepper ended this bed with spheres 5.6e-17
    # below the floor at 0.1, and --read-data refused its own state. Walls take the overlaps' tolerance.
    lattice = [(0.5 + 1.0 * i, 0.5 + 1.0 * j, 0.6 + 1.5 * k) for i in range(5) for j in range(5) for k in range(3)]
    args = ("--boundary", "p,p,w", "--gravity", "0,0,-1", "--restitution", "0.3")
    out = tmp_path / "settled.data"
    p = run(hs, "--read-data", bed_file(tmp_path / "bed.data", lattice), *args, "--time", 40, "--write-data", out)
    assert p.returncode == 0, p.stderr
    again = run_json(hs, "--read-data", out, *args, "--time", 5, "--engine", engine)
    assert again["max_overlap"] <= again["overlap_tolerance"] and again["warnings"] == []
    past = bed_file(tmp_path / "past.data", [(2.0, 2.0, 0.45 - 5.6e-17)])
    assert run(hs, "--read-data", past, *args, "--time", 1, "--engine", engine).returncode == 0
    far = run(hs, "--read-data", bed_file(tmp_path / "far.data", [(2.0, 2.0, 0.45 - 1e-9)]), *args, "--steps", 1)
    assert far.returncode == 2 and "far.data:12: atom 1: z = " in far.stderr and "outside the wall" in far.stderr
