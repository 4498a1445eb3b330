"""The examples of docs/python.md run: every ```python block, in order, in one namespace, in an
empty directory."""
import os
import re
import subprocess
import sys
from pathlib import Path

import hardsphere

DOC = Path(__file__).resolve().parents[2] / "docs" / "python.md"


def blocks():
    return re.findall(r"^```python\n(.*?)^```", DOC.read_text(), re.M | re.S)


def test_docs_have_examples():
    assert len(blocks()) >= 5


def test_docs_examples_run(tmp_path):
    code = "\n".join(blocks())
    # The module as this test imported it, wherever the working directory is.
    env = dict(os.environ, PYTHONPATH=str(Path(hardsphere.__file__).resolve().parents[1]), MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env, capture_output=True, text=True,
                       timeout=240)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "snapshot.png").read_bytes()[:4] == b"\x89PNG"
    for f in ("out.data", "out.dump", "pair.data"):
        assert (tmp_path / f).stat().st_size > 0
    assert "restitution 1.5 must be in (0, 1]" in p.stdout and "cannot open data file" in p.stdout
