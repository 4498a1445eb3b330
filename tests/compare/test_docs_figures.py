"""compare.docs_figures: redraws the three documentation figures from the committed data (no
hardsphere program needed), and its Pareto fronts are staircases: cheaper settings have larger errors."""
import subprocess
import sys

from compare import docs_figures

NAMES = ["pareto_time_error.png", "eos_kolafa.png", "collisions_per_second.png"]


def test_docs_figures(tmp_path):
    p = subprocess.run([sys.executable, "-m", "compare.docs_figures", "--out", str(tmp_path)], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 0, p.stderr
    for name in NAMES:
        assert (tmp_path / name).stat().st_size > 10000, name
    lines = p.stdout.splitlines()
    for tag in ("] pareto:", "] eos:", "] collisions/s:"):
        assert any(tag in ln for ln in lines), tag


def test_pareto_front_is_monotone(tmp_path):
    mod = docs_figures
    assert mod.pareto_front([(0.3, 1.0), (0.1, 3.0), (0.2, 2.0), (0.25, 2.5), (0.05, 2.9)]) == \
        [(0.05, 2.9), (0.2, 2.0), (0.3, 1.0)]
    _, fronts = mod.fig_pareto(tmp_path)
    assert fronts
    for front in fronts.values():
        errs, costs = zip(*front)
        assert all(a < b for a, b in zip(errs, errs[1:]))  # error grows along the front ...
        assert all(a > b for a, b in zip(costs, costs[1:]))  # ... as the cost falls
