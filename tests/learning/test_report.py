"""Table 3 and the learning curves from constructed records."""

from __future__ import annotations

from pathlib import Path

from voxposer.learning.report import table3, write_curves

from .toy_door import trajectory


def _rec(prior: bool, seed: int, it: int, t: float, success: float, final: bool = False,
         converged: bool = False) -> dict:
    r = {"task": "door", "prior": prior, "seed": seed, "iteration": it, "interaction_s": t,
         "eval_success": success, "transitions": 10 * (it + 1), "loss": 0.1}
    if final:
        r.update(final=True, converged=converged,
                 stopped="converged" if converged else "time limit")
    return r


def test_table_shows_each_arm_beside_the_paper() -> None:
    records = [_rec(True, 0, 0, 20, 0.3), _rec(True, 0, 1, 40, 1.0, True, True),
               _rec(True, 1, 0, 60, 1.0, True, True),
               _rec(False, 0, 0, 90, 0.0), _rec(False, 0, 1, 180, 0.0, True)]
    zs = [trajectory(0), trajectory(1)]
    text = table3(records, zs)
    door = next(line for line in text.splitlines() if line.startswith("| door"))
    assert "0% (0/2)" in door  # the toy τ₀ never opens the door
    assert "100.0 ± 0.0 (n=2)" in door and "50.0 ± 10.0 s" in door
    assert "0.0 ± 0.0 (n=1)" in door and "limit (180 s; 0/1 converged)" in door
    assert "88.3% (142.3 s)" in door


def test_unfinished_runs_are_marked(tmp_path: Path) -> None:
    text = table3([_rec(True, 0, 0, 20, 0.5)], [trajectory()])
    assert "1 unfinished" in text
    png = write_curves([_rec(True, 0, 0, 20, 0.5), _rec(False, 0, 0, 20, 0.0)],
                       tmp_path / "c.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
