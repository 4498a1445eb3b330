"""LAMMPS's own data files through the command line (issue 42, item 5). The files in data/lammps/
were written by three LAMMPS releases (make_files.sh: 29 Sep 2021 with pair_style hardsphere,
4 Feb 2025, 4 Jul 2026) with the coefficient sections of their pair styles, 'pair ij', type labels
and tilt factors. Each is read as it is (pair_style hardsphere's coefficients checked, every other
section skipped with a warning), and LAMMPS -> hardsphere -> LAMMPS keeps every per-atom value bit
for bit: ids, types, diameters, densities, positions, image flags, velocities and spins."""
import glob
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hs_run import run

from compare import lammps_files as lf

DATA = Path(__file__).parent / "data" / "lammps"
SKIPPED = "skipped"
# Each file and the sections its run must report as skipped (none: everything was used or checked).
FILES = {
    "lmp2021_hardsphere.data": [],
    "lmp2021_hardsphere_pairij.data": [],
    "lmp2021_zero.data": ["Pair Coeffs # zero skipped"],
    "lmp2025_granular.data": [],
    "lmp2025_zero_pairij.data": ["PairIJ Coeffs # zero skipped"],
    "lmp2026_labels_ljcut.data": ["Atom Type Labels skipped", "Pair Coeffs # lj/cut skipped"],
    "lmp2026_tilt0.data": ["Atom Type Labels skipped"],
}
FIELDS = ("ids", "types", "diameter", "density", "pos", "image", "vel", "omega")


def lammps_binaries():
    """Debian's lmp and the releases built in ~/.cache/hardsphere (scripts/setup.sh), if present."""
    found = [shutil.which("lmp")] + sorted(glob.glob(os.path.expanduser("~/.cache/hardsphere/lammps-*/prefix/bin/lmp")))
    return [b for b in found if b]


def same(a, b, fields=FIELDS):
    """The fields that differ between two SphereData, bit for bit."""
    return [k for k in fields if np.asarray(getattr(a, k)).tobytes() != np.asarray(getattr(b, k)).tobytes()]


def through_hardsphere(hs, tmp_path, name, *args):
    out = tmp_path / ("hs_" + name)
    p = run(hs, "--read-data", DATA / name, "--boundary", "p,p,w", "--steps", 0, *args, "--write-data", out)
    return p, out


@pytest.mark.parametrize("name", sorted(FILES))
def test_lammps_files_are_read_and_written_back_bit_for_bit(hs, tmp_path, name):
    p, out = through_hardsphere(hs, tmp_path, name)
    assert p.returncode == 0, p.stderr
    warnings = [line for line in p.stderr.splitlines() if line.startswith("hardsphere: warning:")]
    assert len(warnings) == len(FILES[name]), warnings
    for w, expected in zip(warnings, FILES[name]):
        assert f"{name}:" in w and expected in w, (w, expected)
    assert same(lf.read_data(DATA / name), lf.read_data(out)) == []


def test_a_run_moves_the_spheres_and_keeps_the_spins(hs, tmp_path):
    p, out = through_hardsphere(hs, tmp_path, "lmp2021_hardsphere.data", "--dt", 0.01)
    p = run(hs, "--read-data", DATA / "lmp2021_hardsphere.data", "--boundary", "p,p,w", "--steps", 100,
            "--write-data", out)
    assert p.returncode == 0, p.stderr
    before, after = lf.read_data(DATA / "lmp2021_hardsphere.data"), lf.read_data(out)
    assert same(before, after, ("ids", "types", "diameter", "density", "omega")) == []
    assert not np.array_equal(before.pos, after.pos)


@pytest.mark.parametrize("edit,needles", [
    # pair_style hardsphere's contact distance must cover its atoms, as fix hardsphere requires
    (("\n1 1.5\n", "\n1 0.8\n"), ["lmp2021_hardsphere.data:12: contact distance 0.8 of atom types 1 and 1",
                                  "diameter 1 of atom 1 (line 17)", "fix hardsphere refuses it"]),
    (("\n2 1.5\n", "\n2 1.2\n"), [":13: contact distance 1.2 of atom types 2 and 2", "atom 2 (line 18)"]),
    (("\n1 1.5\n", "\n1 1.5 2\n"), [":12: pair_style hardsphere's Pair Coeffs row has 3 words"]),
    (("\n2 1.5\n", "\n1 1.5\n"), [":13: Pair Coeffs row for type 1 given twice (first at line 12)"]),
    (("\n2 1.5\n", "\n3 1.5\n"), [":13: type '3' is out of range (1..2, the header's atom types)"]),
    (("\n2 1.5\n", "\n"), ["Pair Coeffs section ends after 1 of 2 rows: found section 'Atoms'"]),
    (("0 6 zlo zhi\n", "0 6 zlo zhi\n0.5 0 0 xy xz yz\n"), [":9: triclinic box (tilt factors xy xz yz = 0.5 0 0)"]),
    (("2 atom types\n", "2 atom types\n1 bonds\n"), [":5: 1 bonds are not supported"]),
    (("Pair Coeffs # hardsphere", "Bond Coeffs # harmonic"), [":10: Bond Coeffs section, but the header has no "
                                                               "bond types"]),
])
def test_malformed_coefficients_and_boxes_are_refused(hs, tmp_path, edit, needles):
    text = (DATA / "lmp2021_hardsphere.data").read_text()
    assert edit[0] in text
    bad = tmp_path / "lmp2021_hardsphere.data"
    bad.write_text(text.replace(edit[0], edit[1], 1))
    p = run(hs, "--read-data", bad, "--boundary", "p,p,w", "--steps", 0)
    assert p.returncode == 2 and p.stderr.startswith("hardsphere: error: "), p.stderr
    for n in needles:
        assert n in p.stderr, (n, p.stderr)


@pytest.mark.parametrize("edit,warning", [
    # LAMMPS refuses per-type masses for atom_style sphere; hardsphere reads them and says it does not use them
    (("\nAtoms # sphere", "\nMasses\n\n1 2.0\n2 3.0\n\nAtoms # sphere"),
     "lmp2025_granular.data:10: Masses skipped: atom_style sphere takes each atom's mass from its density"),
    # LAMMPS resets image flags on non-periodic axes with a warning: so does hardsphere
    (("4.5 1.2 2 1 -2 0", "4.5 1.2 2 1 -2 3"),
     "lmp2025_granular.data:14: atom 3: image flag 3 on the wall axis z set to 0, as LAMMPS does"),
])
def test_values_read_and_not_used_are_named(hs, tmp_path, edit, warning):
    text = (DATA / "lmp2025_granular.data").read_text()
    assert edit[0] in text
    f = tmp_path / "lmp2025_granular.data"
    f.write_text(text.replace(edit[0], edit[1], 1))
    p = run(hs, "--read-data", f, "--boundary", "p,p,w", "--steps", 0)
    assert p.returncode == 0 and f"hardsphere: warning: {f.parent}/{warning}" in p.stderr, p.stderr


def test_a_tilted_box_is_refused_naming_its_line(hs, tmp_path):
    p, _ = through_hardsphere(hs, tmp_path, "lmp2026_tilted.data")
    assert p.returncode == 2, p.stderr
    assert "lmp2026_tilted.data:9: triclinic box (tilt factors xy xz yz = 0.5 0 0) is not supported" in p.stderr


@pytest.mark.parametrize("lmp", lammps_binaries() or [None])
def test_lammps_reads_what_hardsphere_wrote(hs, tmp_path, lmp):
    """LAMMPS -> hardsphere -> LAMMPS: each LAMMPS found reads hardsphere's file and writes it back
    unchanged (densities to 2 units in the last place: LAMMPS 4 Jul 2026 computes the mass in
    another order and writes the density back from it, issue 42 item 9)."""
    if lmp is None:
        pytest.skip("no LAMMPS found")
    names, deck = sorted(FILES), ""
    for k, name in enumerate(names):  # one LAMMPS run for all files
        p, out = through_hardsphere(hs, tmp_path, name)
        assert p.returncode == 0, p.stderr
        deck += f"clear\nunits lj\natom_style sphere\nboundary p p f\nread_data {out}\nwrite_data back{k}.data\n"
    (tmp_path / "in.back").write_text(deck)
    q = subprocess.run([lmp, "-in", "in.back", "-log", "none", "-screen", "none"], cwd=tmp_path, capture_output=True,
                       text=True, timeout=120)
    assert q.returncode == 0, (q.stdout, q.stderr)
    for k, name in enumerate(names):
        a, b = lf.read_data(tmp_path / ("hs_" + name)), lf.read_data(tmp_path / f"back{k}.data")
        assert same(a, b, [f for f in FIELDS if f != "density"]) == [], name
        assert np.all(np.abs(b.density - a.density) <= 2 * np.spacing(a.density)), name
