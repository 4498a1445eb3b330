#!/usr/bin/env python3
"""Fails when a C++ source file of the project differs from what .clang-format makes of it.

  check_format.py --clang-format PATH --root SOURCE_DIR
"""
import argparse
import subprocess
import sys
from pathlib import Path

DIRS = ("standalone", "plugin", "python", "bench", "tests")
SUFFIXES = {".cpp", ".hpp", ".h"}

ap = argparse.ArgumentParser()
ap.add_argument("--clang-format", required=True)
ap.add_argument("--root", required=True)
a = ap.parse_args()
root = Path(a.root)
files = sorted(p for d in DIRS for p in (root / d).rglob("*") if p.suffix in SUFFIXES and p.is_file())
bad = [f for f in files if subprocess.run([a.clang_format, "--dry-run", "--Werror", str(f)],
                                            capture_output=True).returncode != 0]
for f in bad:
    print(f"not formatted: {f.relative_to(root)} (clang-format -i {f.relative_to(root)})")
print(f"{len(files) - len(bad)} of {len(files)} C++ files formatted")
sys.exit(1 if bad or not files else 0)
