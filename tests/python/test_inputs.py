"""Values on their way into C++ arrive as given or are refused naming them as given: paths are
not cut at a NUL, integers are not wrapped or truncated, reals are not made of other kinds
(docs/python.md#errors, docs/robustness.md#python-module)."""
import os
import pathlib

import numpy as np
import pytest

import hardsphere as hs

BOX = hs.Box(10.0)
PAIR = [[1.0, 1.0, 1.0], [3.0, 3.0, 3.0]]


@pytest.fixture(scope="module")
def gas():
    return hs.System.random(n=20, phi=0.1, seed=1)


# ---- paths (issue 42 item 8): C would end a path at its NUL and write or read another file

NUL_CALLS = {
    "System.write_data": lambda g, p: g.write_data(p),
    "Stepper.write_data": lambda g, p: hs.Stepper(g).write_data(p),
    "EventEngine.write_dump": lambda g, p: hs.EventEngine(g).write_dump(p),
    "Stepper.write_dump": lambda g, p: hs.Stepper(g).write_dump(p),
    "DumpWriter": lambda g, p: hs.DumpWriter(p),
    "from_data": lambda g, p: hs.System.from_data(p),
}


@pytest.mark.parametrize("call", NUL_CALLS)
@pytest.mark.parametrize("kind", [str, bytes, pathlib.PurePosixPath])
def test_path_with_nul_is_refused_and_touches_nothing(gas, tmp_path, call, kind):
    victim = tmp_path / "victim"
    victim.write_text("precious\n")
    raw = str(victim) + "\0.data"
    path = os.fsencode(raw) if kind is bytes else kind(raw)
    name = call.split(".")[-1]
    with pytest.raises(ValueError) as err:
        NUL_CALLS[call](gas, path)
    assert str(err.value) == (f"{name} {os.fspath(path)!r}: a path cannot contain a NUL character "
                              "(the operating system would end it there)")
    assert victim.read_text() == "precious\n" and os.listdir(tmp_path) == ["victim"]


def test_paths_may_be_bytes_or_pathlike(gas, tmp_path):
    gas.write_data(tmp_path / "a.data")
    hs.Stepper(gas).write_dump(os.fsencode(tmp_path / "b.dump"))
    with hs.DumpWriter(tmp_path / "c.dump") as d:
        d.write(hs.Stepper(gas))
    assert np.array_equal(hs.System.from_data(tmp_path / "a.data").positions, gas.positions)
    assert sorted(os.listdir(tmp_path)) == ["a.data", "b.dump", "c.dump"]
    with pytest.raises(TypeError, match="^write_data: a path is a str, bytes or os.PathLike, not int$"):
        gas.write_data(3)


def test_title_is_one_line(gas, tmp_path):
    """A line break in the title would put its rest among the header lines: an unreadable file."""
    for title in ["a\n5 atoms", "a\rb", "a\0b"]:
        with pytest.raises(ValueError, match=r"^title '.*' (must be one line|contains a NUL)"):
            gas.write_data(str(tmp_path / "t.data"), title=title)
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("call", [lambda: hs.Box(10.0, boundary="p\0w"),
                                  lambda: hs.System.random(n=10, boundary="p\0"),
                                  lambda: hs.Stepper(hs.System.random(n=10), precision="double\0"),
                                  lambda: hs.Stepper(hs.System.random(n=10), cells="auto\0")])
def test_keyword_text_with_nul_is_refused_whole(call):
    """The message shows the whole value, not the part before the NUL."""
    with pytest.raises(ValueError, match=r"'[a-z]+\\x00[a-z]*' contains a NUL character"):
        call()


# ---- integers (issue 42 item 10): checked as a data file's, never wrapped or truncated

@pytest.mark.parametrize("images,message", [
    (2**31, "images[0, 0] = 2147483648 is out of range (32-bit integers)"),
    (2**40, "images[0, 0] = 1099511627776 is out of range (32-bit integers)"),
    (-2**31 - 1, "images[0, 0] = -2147483649 is out of range (32-bit integers)"),
    (0.7, "images[0, 0] = 0.7 is not an integer"),
    (float("nan"), "images[0, 0] = nan is not an integer"),
])
def test_images_out_of_range_or_fractional(images, message):
    with pytest.raises(ValueError) as err:
        hs.System(BOX, PAIR, images=[[images, 0, 0], [0, 0, 0]])
    assert str(err.value) == message


@pytest.mark.parametrize("kw,message", [
    ({"types": [1e10, 1]}, "types[0] = 10000000000.0 is out of range (types are 1 to 2147483647)"),
    ({"types": [2**40, 1]}, "types[0] = 1099511627776 is out of range (types are 1 to 2147483647)"),
    ({"types": [1, 0]}, "types[1] = 0 is out of range (types are 1 to 2147483647)"),
    ({"ids": [1.9, 2]}, "ids[0] = 1.9 is not an integer"),
    ({"ids": np.array([2**64 - 1, 2], dtype=np.uint64)},
     "ids[0] = 18446744073709551615 is out of range (ids are 1 to 9223372036854775807)"),
    ({"ids": [2**63, 1]}, "ids[0] = 9223372036854775808 is out of range (ids are 1 to 9223372036854775807)"),
    ({"ids": [2.0**63, 1]}, "ids[0] = 9.223372036854776e+18 is out of range (ids are 1 to 9223372036854775807)"),
    ({"ids": [2**53 + 1, 2**64]}, "ids[1] = 18446744073709551616 is out of range (ids are 1 to 9223372036854775807)"),
    ({"ids": [2**100, 1]}, "ids[0] = 1267650600228229401496703205376 is out of range "
                           "(ids are 1 to 9223372036854775807)"),
    ({"ids": [1, "2"]}, "ids must be integers, not an array of <U21"),
    ({"ids": [True, False]}, "ids must be integers, not an array of bool"),
    ({"types": [1, 2, 3]}, "types must have shape (2,) with N = 2"),
])
def test_ids_and_types_as_given(kw, message):
    with pytest.raises(ValueError) as err:
        hs.System(BOX, PAIR, **kw)
    assert str(err.value) == message


def test_integral_values_of_any_numeric_kind_are_taken_exactly():
    s = hs.System(BOX, PAIR, ids=np.array([2**62 + 1, 7], dtype=np.uint64), types=[3.0, np.int8(2)],
                  images=np.array([[1.0, -2.0, 0.0], [2**31 - 1, -2**31, 0]], dtype=object))
    assert s.ids.tolist() == [2**62 + 1, 7] and s.types.tolist() == [3, 2]
    assert s.images.tolist() == [[1, -2, 0], [2**31 - 1, -2**31, 0]]
    assert hs.System(BOX, PAIR, ids=np.array([9, 8], dtype=np.longdouble)).ids.tolist() == [9, 8]


def test_wall_axes_have_no_images_as_in_a_data_file(tmp_path):
    """The data reader sets image flags on wall axes to 0 (LAMMPS's read_data resets them too):
    a System given images there does the same, so both give the same state and files."""
    box = hs.Box(10.0, boundary="p,w,w")
    s = hs.System(box, [[1.0, 1.0, 1.0]], images=[[1, 1, 1]])
    assert s.images.tolist() == [[1, 0, 0]]
    assert s.unwrapped_positions.tolist() == [[11.0, 1.0, 1.0]]
    s.write_data(tmp_path / "s.data")
    text = (tmp_path / "s.data").read_text()
    assert text.replace(" 1 0 0\n", " 1 1 1\n") != text  # the flags as written: 1 0 0
    (tmp_path / "f.data").write_text(text.replace(" 1 0 0\n", " 1 1 1\n"))
    f = hs.System.from_data(tmp_path / "f.data", boundary="p,w,w")
    assert f.images.tolist() == s.images.tolist() and np.array_equal(f.positions, s.positions)
    with pytest.raises(ValueError, match=r"^images\[0, 2\] = 2147483648 is out of range"):
        hs.System(box, [[1.0, 1.0, 1.0]], images=[[0, 0, 2**31]])  # checked on wall axes too


# ---- reals: numbers only, the shapes the docs give

@pytest.mark.parametrize("kw,message", [
    ({"positions": np.array(PAIR, dtype=complex)}, "positions must be real numbers, not an array of complex128"),
    ({"positions": [["1", "1", "1"], ["3", "3", "3"]]}, "positions must be real numbers, not an array of <U1"),
    ({"positions": [[1, 1], [3, 3]]}, "positions must have shape (N, 3)"),
    ({"positions": [[1, 1, 1], [3, 3]]}, "positions must have shape (N, 3)"),
    ({"velocities": [[None, 0, 0], [0, 0, 0]]}, "velocities[0, 0] = None is not a real number"),
    ({"omegas": [[2**1024, 0, 0], [0, 0, 0]]},
     "omegas[0, 0] = " + str(2**1024)[:64] + "... is too large for a double"),
    ({"radii": "0.5"}, "radii must be real numbers, not str"),
    ({"radii": [0.5, 0.5, 0.5]}, "radii must be a number or have shape (2,) with N = 2"),
    ({"masses": True}, "masses must be real numbers, not bool"),
])
def test_real_arrays_are_numbers(kw, message):
    args = {"positions": PAIR, **kw}
    with pytest.raises(ValueError) as err:
        hs.System(BOX, **args)
    assert str(err.value) == message


def test_numpy_scalars_are_numbers():
    s = hs.System(hs.Box(np.float32(10.0)), PAIR, radii=np.float32(0.25), masses=np.int64(2))
    assert s.radii.tolist() == [0.25, 0.25] and s.masses.tolist() == [2.0, 2.0] and s.box.lengths[0] == 10.0


@pytest.mark.parametrize("call,message", [
    (lambda: hs.System.random(n=1.5), "n = 1.5 is not a whole number"),
    (lambda: hs.System.random(n=10, seed=-1), "seed = -1 is out of range (0 to 18446744073709551615)"),
    (lambda: hs.System.random(n=10, seed=2**64), "seed = 18446744073709551616 is out of range "
                                                 "(0 to 18446744073709551615)"),
    (lambda: hs.System.random(n=10, phi=float("inf")), "phi inf must be positive and finite"),
    (lambda: hs.System.random(n=10, temperature=2.0, speed=1.0),
     "temperature and speed both set the velocities; give one"),
    (lambda: hs.System.random(n=10, inertia=0.5), "inertia 0.5 sets the spins' distribution: it needs "
                                                  "rotational_temperature (without it the spheres do not spin)"),
    (lambda: hs.Stepper(hs.System.random(n=10)).run(steps=1.5), "steps = 1.5 is not a whole number"),
    (lambda: hs.Stepper(hs.System.random(n=10)).run(steps=2**63),
     "steps = 9223372036854775808 is out of range (-9223372036854775808 to 9223372036854775807)"),
    (lambda: hs.Stepper(hs.System.random(n=10)).run(steps=10, every=2),
     "every = 2 needs a callback (it says when to call it)"),
    (lambda: hs.EventEngine(hs.System.random(n=50)).run(time=1.0, every=0.5),
     "every = 0.5 needs a callback (it says when to call it)"),
    (lambda: hs.EventEngine(hs.System.random(n=50)).run(time=1.0, blocks=2**31),
     "blocks = 2147483648 is more than 1000000"),
    (lambda: hs.Stepper(hs.System.random(n=10)).observables(histogram_bins=10**9),
     "histogram_bins 1000000000 is more than 1000000"),
])
def test_numbers_as_given(call, message):
    with pytest.raises(ValueError) as err:
        call()
    assert str(err.value) == message


def test_whole_numbers_given_as_integral_floats_or_numpy_ints():
    s = hs.System.random(n=np.int32(10), seed=np.uint64(2**64 - 1))
    assert s.n == 10 and s.seed == 2**64 - 1
    sim = hs.Stepper(s)
    sim.run(steps=20.0)
    assert sim.steps == 20
    with pytest.raises(TypeError, match="^steps must be a whole number, not bool$"):
        sim.run(steps=True)


def test_event_callback_interval_below_the_clock_is_refused():
    """An interval the clock cannot add to the time would call back at one time forever."""
    ev = hs.EventEngine(hs.System.random(n=50, phi=0.1, seed=1))
    ev.run(time=2.0)
    with pytest.raises(ValueError, match=r"^every = 1e-300 is below the resolution of the clock at time 3 "):
        ev.run(time=1.0, every=1e-300, callback=lambda e: None)
    assert ev.time == 2.0


def test_box_repr_shows_the_box_exactly():
    """repr showed six decimals: a box 1e-7 long was 'lengths=(0.000000, ...)'."""
    for box in [hs.Box(1e-7), hs.Box((0.1, 2.5e-9, 3e5), boundary="p,w,p", lo=(-1.25, 1e-300, 7))]:
        again = eval(repr(box), {"Box": hs.Box})
        assert (again.lengths, again.lo, again.boundary) == (box.lengths, box.lo, box.boundary)
    assert repr(hs.Box(10.0)) == "Box(lengths=(10, 10, 10), boundary='p,p,p', lo=(0, 0, 0))"
