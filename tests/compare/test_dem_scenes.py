"""compare.dem_scenes: the bed measurements on states whose answer is known, and the soft input
it derives from LAMMPS's in.pour."""
import math

import numpy as np
import pytest

from compare import dem_scenes
from compare.lammps_files import spheres


def lattice():
    """Unit spheres on a simple cubic lattice of spacing 1 filling a 4 x 4 x 10 box (z from 0)."""
    g = np.arange(0.5, 4, 1.0)
    pos = [(x, y, z) for x in g for y in g for z in np.arange(0.5, 10, 1.0)]
    return spheres(pos, box=[[0, 4], [0, 4], [0, 10]])


def test_slab_fraction_of_a_simple_cubic_lattice():
    d = lattice()
    # every unit cell holds one sphere: pi / 6 in any slab of whole layers, and in any slab at all
    assert dem_scenes.slab_fraction(d, 1.0, 4.0, 16.0) == pytest.approx(math.pi / 6, rel=1e-12)
    assert dem_scenes.slab_fraction(d, 2.25, 3.25, 16.0) == pytest.approx(math.pi / 6, rel=1e-12)


def test_largest_overlap_across_the_periodic_face():
    d = lattice()
    assert dem_scenes.largest_overlap(d) == pytest.approx(0.0, abs=1e-12)  # touching, not overlapping
    d.pos[0, 0] = 0.45  # 0.95 from the image of its neighbour at x = 3.5 across the face x = 0
    assert dem_scenes.largest_overlap(d) == pytest.approx(0.05, rel=1e-9)


def test_soft_pour_input_settles_instead_of_the_chute(tmp_path):
    if not (dem_scenes.EXAMPLES / "pour" / "in.pour").is_file():
        pytest.skip("lammps-examples not installed")
    text = dem_scenes.soft_pour_input("end.data")
    assert "gravity 1.0 chute" not in text and text.count("unfix\t\tins") == 1
    assert text.rstrip().endswith("write_data\tend.data") and "c_zm" in text
