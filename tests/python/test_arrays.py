"""Array shapes, dtypes and ownership: read-only, their memory kept alive by their base."""
import gc

import numpy as np
import pytest

import hardsphere as hs

FIELDS = {"positions": ((3,), np.float64), "velocities": ((3,), np.float64), "radii": ((), np.float64),
          "masses": ((), np.float64), "ids": ((), np.int64), "types": ((), np.int32), "images": ((3,), np.int32),
          "omegas": ((3,), np.float64)}


@pytest.fixture
def system():
    return hs.System.random(n=200, phi=0.2, seed=2)


@pytest.mark.parametrize("name", FIELDS)
def test_system_arrays_are_read_only_views(system, name):
    a = getattr(system, name)
    tail, dtype = FIELDS[name]
    assert a.shape == (200, *tail) and a.dtype == dtype
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0] = 0
    assert a.base is system  # a view of the System's memory
    assert np.shares_memory(a, getattr(system, name))


def test_system_view_outlives_its_name():
    a = hs.System.random(n=50, phi=0.1, seed=4).positions
    gc.collect()
    b = a.copy()
    gc.collect()
    assert np.array_equal(a, b) and a.base is not None


@pytest.mark.parametrize("engine", ["stepper", "event"])
@pytest.mark.parametrize("name", FIELDS)
def test_engine_arrays_are_read_only_snapshots(system, engine, name):
    sim = hs.Stepper(system) if engine == "stepper" else hs.EventEngine(system)
    a = getattr(sim, name)
    tail, dtype = FIELDS[name]
    assert a.shape == (200, *tail) and a.dtype == dtype
    assert not a.flags.writeable
    assert np.shares_memory(a, getattr(sim, name))  # one snapshot per state
    before = a.copy()
    sim.run(steps=5) if engine == "stepper" else sim.run(time=0.05)
    assert np.array_equal(a, before)  # a later run does not touch it ...
    if name in ("positions", "velocities"):
        assert not np.array_equal(getattr(sim, name), before)  # ... it makes a new snapshot
    del sim
    gc.collect()
    assert np.array_equal(a, before)  # the snapshot outlives the engine


def test_engine_arrays_in_id_order(tmp_path):
    s = hs.System.random(n=300, phi=0.2, seed=9)
    ids = np.arange(300, 0, -1)  # given in reverse order
    r = hs.System(s.box, s.positions, s.velocities, ids=ids)
    assert np.array_equal(r.ids, ids)
    for sim in (hs.Stepper(r), hs.EventEngine(r)):
        assert np.array_equal(sim.ids, np.arange(1, 301))
        assert np.array_equal(sim.positions, r.positions[::-1])


def test_system_from_arrays_wraps_and_counts_images():
    box = hs.Box(10.0, boundary="p,p,w")
    s = hs.System(box, [[11.0, -1.0, 5.0], [3.0, 3.0, 3.0]], velocities=[[1, 0, 0], [0, 0, 1]], radii=[0.5, 0.7],
                  masses=2.0, types=[1, 2])
    assert np.array_equal(s.positions, [[1.0, 9.0, 5.0], [3.0, 3.0, 3.0]])
    assert np.array_equal(s.images, [[1, -1, 0], [0, 0, 0]])
    assert np.array_equal(s.unwrapped_positions, [[11.0, -1.0, 5.0], [3.0, 3.0, 3.0]])
    assert s.box.boundary == "p,p,w" and s.box.lengths == [10.0, 10.0, 10.0]
    assert np.array_equal(s.types, [1, 2]) and np.array_equal(s.masses, [2.0, 2.0])


def test_freud_box_tuple(system):
    box, points = system.freud_box()
    L = system.box.lengths
    assert box == [L[0], L[1], L[2], 0.0, 0.0, 0.0]
    assert points.shape == (200, 3)
    assert np.all(points >= -np.array(L) / 2) and np.all(points < np.array(L) / 2)
    assert np.allclose(points + np.array(L) / 2, system.positions)
