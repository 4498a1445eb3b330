"""compare.granular_figures: barometric gas, resting bed and strong dissipation in both engines (quick mode)."""
import json
import subprocess
import sys


def test_granular_figures_quick(hs, tmp_path):
    p = subprocess.run([sys.executable, "-m", "compare.granular_figures", "--hardsphere", hs, "--out",
                        str(tmp_path), "--quick"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    for name in ("barometric", "bed", "collapse"):
        assert (tmp_path / f"granular_{name}.png").stat().st_size > 10000
    res = json.loads((tmp_path / "granular.json").read_text())
    assert res["pass"] and res["quick"]
    assert [b["engine"] for b in res["barometric"]] == ["stepper", "event"]
    for b in res["barometric"]:
        # over 10 seeds the quick ratio had mean +4.0% / +3.0% and sd 3.5% / 3.3% (stepper / event)
        assert abs(b["ratio"] - 1) < 0.18
