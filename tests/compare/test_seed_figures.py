"""compare.seed_figures quick mode: writes all five files, and the scaling it measures is the
seed paper's (checks with wide margins, not timing assertions)."""
import json

from compare import seed_figures


def test_seed_figures_quick(hs, tmp_path):
    lines = []
    res = seed_figures.run(hs, tmp_path, True, progress=lines.append)
    names = ["seed_fig1_ideal_boxes.png", "seed_fig2_linear.png", "seed_fig3_one_box.png"]
    for name in names:
        assert (tmp_path / name).stat().st_size > 1000, name
    assert lines and all(ln.startswith("seed fig:") and "\n" not in ln for ln in lines)
    saved = json.loads((tmp_path / "seed_figures.json").read_text())
    assert saved["fits"] == res["fits"]
    md = (tmp_path / "seed_figures.md").read_text()
    assert md.startswith("### ") and all(f"({name})" in md for name in names)

    ideal, one, fits = saved["ideal"], saved["one_box"], saved["fits"]
    assert len(ideal) >= 3 and len(one) >= 3
    for r in ideal + one:
        assert r["seconds_per_step_median"] > 0 and len(r["seconds_per_step"]) == r["repeats"]
    # All pairs in one box cost ~N^2 per step, the ideal grid ~N: far apart even on a noisy machine.
    assert fits["one_box"]["slope"] - fits["ideal"]["slope"] > 0.5
    assert fits["one_box"]["slope"] > 1.5
    # The ideal number of boxes grows with N (16x from the first to the last N).
    cells = [r["cells"] for r in sorted(ideal, key=lambda r: r["n"])]
    assert cells[-1] > cells[0] and fits["ideal_boxes"]["slope"] > 0.3
