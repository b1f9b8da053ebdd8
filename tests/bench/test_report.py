"""The report from small synthetic records (no simulation): provenance and version checks, the
reference / constraint-blind / model comparison, LLM-call totals and the Table 2 layout."""

from __future__ import annotations

import re
from typing import Any

import pytest

from voxposer.bench.config import Tolerances
from voxposer.bench.report import markdown
from voxposer.bench.report_tables import BLIND_FLAG
from voxposer.errors import ConfigError


def _rec(task: str, split: str = "seen", seed: int = 0, *, llm: str = "default",
         success: bool = True, instructions: str = "seen", code_hash: str = "c0de",
         calls: int = 0, cached: int = 0, seed_set: str = "dev",
         method: str = "voxposer") -> dict[str, Any]:
    return {"task": task, "split": split, "seed": seed, "method": method, "llm": llm,
            "instructions": instructions, "seed_set": seed_set, "code_hash": code_hash,
            "prompt_hash": "9f0a", "git_commit": "1234567890abcdef", "git_dirty": True,
            "success": success, "error": None, "timings_s": {"total": 2.0},
            "llm_calls": calls, "llm_cached_calls": cached}


def _row(text: str, start: str) -> str:
    (line,) = [ln for ln in text.splitlines() if ln.startswith(start)]
    return line


def test_the_report_refuses_mixed_code_versions() -> None:
    records = [_rec("push_to_pos", code_hash="aaaa"), _rec("push_to_pos", seed=1,
                                                             code_hash="bbbb")]
    with pytest.raises(ConfigError, match=r"2 code versions \(aaaa, bbbb\).*allow-mixed"):
        markdown(records, Tolerances())
    text = markdown(records, Tolerances(), allow_mixed=True)
    assert "MIXED, allowed by --allow-mixed-versions" in text
    assert "`aaaa`" in text and "`bbbb`" in text


def test_the_header_states_version_seeds_and_call_totals() -> None:
    model = [_rec("push_to_pos", seed=s, calls=c, cached=k)
             for s, c, k in ((0, 3, 1), (1, 5, 0), (2, 2, 2))]
    test = [_rec("push_to_pos", "unseen", 100_000 + s, calls=4, seed_set="test")
            for s in range(2)]
    reference = [_rec("push_to_pos", seed=s, llm="reference", calls=6, cached=6)
                 for s in range(2)]
    records = model + test + reference
    text = markdown(records, Tolerances())
    header = text.split("\n## ")[0]
    assert "`c0de` — commit 1234567890, uncommitted changes under src/; prompts `9f0a`; " \
           "7 episodes" in header
    assert "dev (set 0–9999): seeds 0–2 (3 distinct)" in header
    assert "test (set 100000–109999): seeds 100000–100001 (2 distinct)" in header
    calls = sum(r["llm_calls"] for r in model + test)
    cached = sum(r["llm_cached_calls"] for r in model + test)
    assert (calls, cached) == (18, 3)
    assert f"**LLM calls**: {calls} over 5 model episodes, {cached} of them" in header
    assert "**reference-program replays** (no LLM): 12 over 2 episodes" in header


def test_a_blind_cell_above_ten_percent_is_flagged() -> None:
    records = []
    for seed in range(10):  # staying_on: blind 20% (flagged); min_distance: blind 10% (not)
        for task, blind_ok in (("move_to_pos_staying_on_preposition", seed < 2),
                               ("move_to_pos_min_distance", seed < 1)):
            records += [_rec(task, seed=seed, llm="reference"),
                        _rec(task, seed=seed, llm="reference-blind", success=blind_ok),
                        _rec(task, seed=seed, success=seed % 2 == 0)]
    text = markdown(records, Tolerances())
    assert "VoxPoser — reference programs, constraint-blind control (no LLM)" in text
    head = _row(text, "| Task | Split | Constraint |")
    assert head.split(" | ")[3:] == ["reference", "blind", "model: default |"]
    flagged = _row(text, "| move_to_pos_staying_on_preposition | seen |")
    assert f"| 100.0% (10/10) | 20.0% (2/10) {BLIND_FLAG} | 50.0% (5/10) |" in flagged
    fine = _row(text, "| move_to_pos_min_distance | seen |")
    assert "| 100.0% (10/10) | 10.0% (1/10) | 50.0% (5/10) |" in fine and BLIND_FLAG not in fine


def test_table2_layout_splits_instructions_and_attributes() -> None:
    records = []
    for seed in range(4):  # Object Interactions: push_to_pos; Spatial Composition: two tasks
        records += [_rec("push_to_pos", "seen", seed, success=seed < 3),
                    _rec("push_to_pos", "unseen", seed, success=seed < 2),
                    _rec("push_to_pos", "unseen", seed, success=seed < 1, instructions="unseen"),
                    _rec("push_to_pos", "seen", seed, success=False, instructions="unseen"),
                    _rec("move_to_region", "seen", seed),
                    _rec("move_to_preposition", "seen", seed, success=seed < 2)]
    text = markdown(records, Tolerances())
    assert "## VoxPoser — default, unseen instructions" in text
    table2 = text.split("### Table 2 layout: VoxPoser — default")[1]
    oi = _row(table2, "| Object Interactions |").split(" | ")
    assert oi[1:4] == ["75.0% (4 ep)", "50.0% (4 ep)", "25.0% (4 ep)"]  # SI SA, SI UA, UI UA
    assert oi[4:7] == ["64.0%", "60.0%", "65.0%"]  # the paper's VoxPoser
    assert oi[7:10] == ["41.0%", "46.0%", "17.5% |"]  # the paper's LLM + Prim.
    sc = _row(table2, "| Spatial Composition |").split(" | ")
    assert sc[1:4] == ["75.0% (8 ep)", "—", "—"]  # mean of 100% and 50% over two tasks
    assert re.search(r"\| push the \[obj\] to the \[pos\] \| 75\.0% \(3/4\) \| 50\.0% \(2/4\)",
                     text)


def test_unet_mp_rows_stand_beside_the_others_with_the_papers_unet_column() -> None:
    records = []
    for seed in range(2):
        records += [_rec("move_to_region", seed=seed, calls=2),
                    _rec("move_to_region", seed=seed, llm="none", method="unet_mp",
                         success=seed == 0),
                    _rec("push_to_pos", seed=seed, llm="none", method="unet_mp", success=False)]
    text = markdown(records, Tolerances())
    header = text.split("\n## ")[0]
    assert "**LLM calls**: 4 over 2 model episodes" in header
    assert "**learned cost maps** (U-Net + MP, no LLM): 4 episodes" in header
    unet = text.split("## U-Net + MP — learned cost maps (no LLM)")[1].split("\n## ")[0]
    assert "| SA (U-Net + MP, paper) | UA (U-Net + MP, paper) |" in unet
    assert _row(unet, "| move to the [region] |").startswith(
        "| move to the [region] | 50.0% (1/2) | — | 5.0% | 0.0% |")
    assert "## VoxPoser — default" in text  # beside VoxPoser's
    table2 = text.split("### Table 2 layout: U-Net + MP — learned cost maps (no LLM)")[1]
    table2 = table2.split("\n#")[0]
    assert "SI SA (U-Net + MP, paper)" in _row(table2, "| Category |")
    sc = _row(table2, "| Spatial Composition |").split(" | ")
    assert sc[1] == "50.0% (2 ep)" and sc[-3:] == ["53.8%", "3.8%", "25.0% |"]
