"""Running the built `hardsphere run` from the CLI tests."""
import json
import subprocess


def run(hs, *args, cwd=None):
    return subprocess.run([hs, "run", *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=120)


def run_json(hs, *args):
    p = run(hs, *args, "--json", "-")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)
