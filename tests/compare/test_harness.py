"""compare.harness, the one harness of compare/ and bench/: every entry point is listed in its
package's docstring and goes through it, the exit statuses (2 refused input, 3 a failed program),
the command line a report quotes, and a report built by several calls (RowStore)."""
import importlib
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from compare import harness

ROOT = Path(__file__).resolve().parents[2]


def entry_points(package):
    """Modules of the package with a `__main__` block, and the names its docstring lists."""
    files = {p.stem for p in (ROOT / package).glob("*.py") if 'if __name__ == "__main__":' in p.read_text()}
    doc = importlib.import_module(package).__doc__
    listed = set(re.findall(r"^  ([a-z_]+) ", doc, re.M))
    return files, listed


@pytest.mark.parametrize("package", ["compare", "bench"])
def test_every_entry_point_is_listed_and_uses_the_harness(package):
    files, listed = entry_points(package)
    assert files and files <= listed, f"not listed in {package}/__init__.py: {files - listed}"
    for name in files:
        text = (ROOT / package / f"{name}.py").read_text()
        assert "harness.main(main)" in text, name
        for old in ("--exe", "--hs\"", "--program", "--lmp\""):  # the spellings the harness replaced
            assert f'add_argument("{old}' not in text, (name, old)


def test_refused_input_and_a_failed_program(tmp_path):
    def run(*args):
        return subprocess.run([sys.executable, "-m", *args], capture_output=True, text=True, cwd=ROOT, timeout=120)

    p = run("compare.hcs", "--hardsphere", str(tmp_path / "nothing"), "--out", str(tmp_path))
    assert p.returncode == 2 and "error: --hardsphere" in p.stderr and "no such program" in p.stderr
    p = run("bench.mpi_model")  # --out is required
    assert p.returncode == 2 and "--out" in p.stderr
    fake = tmp_path / "hardsphere"
    fake.write_text("#!/bin/sh\necho broken >&2\nexit 5\n")
    fake.chmod(0o755)
    p = run("compare.hcs", "--quick", "--hardsphere", str(fake), "--out", str(tmp_path / "out"))
    assert p.returncode == 3 and "status 5" in p.stderr and "broken" in p.stderr, p.stderr
    assert not (tmp_path / "out" / "hcs.md").exists()


def test_command_line_quotes_paths_from_the_root():
    line = harness.command_line("compare.cooling", ["--out", str(ROOT / "docs" / "reports" / "validation"), "--work",
                                                    "/somewhere/else", "--quick"])
    assert line == "python3 -m compare.cooling --out docs/reports/validation --work DIR --quick"


def test_row_store_keeps_the_rows_of_every_call(tmp_path):
    class Session:
        command = "python3 -m bench.x --n 1"

    store = harness.RowStore(tmp_path, "x")
    store.put("t", (1, 0.3), dict(n=1, v=2.0), Session)
    Session.command = "python3 -m bench.x --n 2"
    harness.RowStore(tmp_path, "x").put("t", (2, 0.3), dict(n=2, v=3.0), Session)
    again = harness.RowStore(tmp_path, "x")
    again.put("t", (1, 0.3), dict(n=1, v=4.0), Session)  # a call replaces the rows it measured
    rows = sorted(harness.RowStore(tmp_path, "x").rows("t"), key=lambda r: r["n"])
    assert [(r["n"], r["v"]) for r in rows] == [(1, 4.0), (2, 3.0)]
    assert all(r["command"] == "python3 -m bench.x --n 2" and r["date"] for r in rows)
    assert len(harness.measured_by(rows)) == 1
    assert json.loads((tmp_path / "x.json").read_text())["tables"]["t"].keys() == {"(1, 0.3)", "(2, 0.3)"}


def test_the_index_of_reports_is_current():
    p = subprocess.run([sys.executable, "-m", "compare.headlines", "--check"], capture_output=True, text=True, cwd=ROOT,
                       timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
