from pathlib import Path

from voxposer.cli import main


def test_plan_demo_writes_a_self_contained_picture(tmp_path: Path) -> None:
    assert main(["plan-demo", "--out", str(tmp_path)]) == 0
    html = (tmp_path / "plan.html").read_text()
    assert "plotly" in html and '<script src="http' not in html  # plotly.js embedded, offline
    assert "greedy (paper release)" in html and "affordance target" in html
