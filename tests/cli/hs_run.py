"""Running the built `hardsphere run` from the CLI tests."""
import json
import subprocess


def run(hs, *args, cwd=None):
    return subprocess.run([hs, "run", *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=120)


def run_json(hs, *args):
    p = run(hs, *args, "--json", "-")
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout)


def refused(p, *needles):
    """A refusal: exit status 2, one `hardsphere: error: ` message holding every needle."""
    assert p.returncode == 2, (p.returncode, p.stdout, p.stderr)
    assert p.stderr.startswith("hardsphere: error: "), p.stderr
    for needle in needles:
        assert needle in p.stderr, (needle, p.stderr)
