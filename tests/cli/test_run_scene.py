"""``voxposer run`` sets up a scene that suits the instruction, and ``--drawer-open`` /
``--place`` override it; ``summary.json`` says what was set and why."""

import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.cli import main
from voxposer.cli.run import scene_layout
from voxposer.cli.run_scene import (
    ASKED_CLOSE,
    ASKED_CLOSE_ANY,
    ASKED_OPEN,
    CLOSE_OPENING_M,
    NAMED,
    OPTION,
    SceneRequest,
    allowed_range,
    choose_scene,
    drawer_requests,
    parse_place,
)
from voxposer.envs.config import WorldConfig
from voxposer.envs.layout import sample_placement
from voxposer.errors import ConfigError


def _open(instruction: str, seed: int = 0, request: SceneRequest | None = None) -> dict:
    layout = scene_layout(instruction, np.random.default_rng(seed), request)
    return {d: v for d, v in layout.drawer_openings.items() if v > 0}


@pytest.mark.parametrize(("instruction", "drawer"), [
    ("close the top drawer", "top"),
    ("close the bottommost drawer", "bottom"),
    ("Close the bottom-most drawer.", "bottom"),
    ("push the top drawer closed", "top"),
    ("slide the middle drawer shut", "middle"),
    ("push in the lower drawer", "bottom"),
    ("close the drawer in the middle", "middle"),
    ("make sure the uppermost drawer is closed", "top"),
    ("the top drawer is open; please close it", "top"),
    ("shut the second drawer from the top", "middle"),
])
def test_a_drawer_the_instruction_asks_to_close_starts_open(instruction: str, drawer: str) -> None:
    assert _open(instruction) == {drawer: CLOSE_OPENING_M}
    choice = choose_scene(instruction, np.random.default_rng(0))
    assert choice.why[f"{drawer} drawer"] == ASKED_CLOSE


@pytest.mark.parametrize("instruction", [
    "open the top drawer", "pull the top drawer out", "pull open the top drawer",
    "open the top drawer, then close it",  # the first request counts: it starts closed
])
def test_a_drawer_to_open_starts_closed(instruction: str) -> None:
    assert _open(instruction) == {}
    assert choose_scene(instruction, np.random.default_rng(0)).why["top drawer"] == ASKED_OPEN


def test_closing_an_unnamed_drawer_opens_one_drawn_from_the_runs_generator() -> None:
    picks = [_open("shut whichever drawer is open", seed) for seed in range(12)]
    assert all(len(p) == 1 and next(iter(p.values())) == CLOSE_OPENING_M for p in picks)
    assert len({next(iter(p)) for p in picks}) > 1  # the generator chooses
    assert picks == [_open("shut whichever drawer is open", seed) for seed in range(12)]
    (which,) = picks[0]
    assert choose_scene("close the open drawer", np.random.default_rng(0)).why[
        f"{which} drawer"] == ASKED_CLOSE_ANY
    assert _open("close all the drawers") == dict.fromkeys(("top", "middle", "bottom"),
                                                           CLOSE_OPENING_M)


@pytest.mark.parametrize("instruction", [
    "push the blue block next to the top drawer", "move close to the top drawer",
    "put the blue block in the top drawer", "move to the top of the blue block",
])
def test_other_mentions_of_drawers_leave_them_closed(instruction: str) -> None:
    assert drawer_requests(instruction) == {} and _open(instruction) == {}


def test_drawer_open_option_replaces_the_automatic_choice() -> None:
    request = SceneRequest.from_options(["bottom", "middle=0.08"])
    assert _open("close the top drawer", request=request) == {"bottom": CLOSE_OPENING_M,
                                                              "middle": 0.08}
    why = choose_scene("close the top drawer", np.random.default_rng(0), request).why
    assert why["bottom drawer"] == OPTION and why["top drawer"] != ASKED_CLOSE
    for bad, words in (("lowest", ("'lowest'", "top, middle, bottom")),
                       ("top=0.5", ("'top=0.5'", "[0, 0.2]"))):
        with pytest.raises(ConfigError) as err:
            SceneRequest.from_options([bad])
        assert all(w in str(err.value) for w in words), str(err.value)


def test_place_puts_a_block_on_the_table_and_refuses_one_off_it() -> None:
    assert parse_place("Blue block=0.05,-0.1") == ("blue block", (0.05, -0.1))
    (xlo, xhi), (ylo, yhi) = allowed_range("block")
    assert (xlo, xhi, ylo, yhi) == pytest.approx((-0.675, 0.275, -0.475, 0.475))
    for bad, words in (("blue block=0.5,0", ("x = 0.5 m", "[-0.675, 0.275]", "[-0.475, 0.475]")),
                       ("blue block=0,-0.6", ("y = -0.6 m", "off the table")),
                       ("silver block=0,0", ("'silver'", "blue, green")),
                       ("blue block=0;0", ("'0;0'", "<x>,<y>")),
                       ("blue cube=0,0", ("<colour> block=<x>,<y>",))):
        with pytest.raises(ConfigError) as err:
            parse_place(bad)
        assert all(w in str(err.value) for w in words), str(err.value)
    with pytest.raises(ConfigError, match="twice"):
        SceneRequest.from_options(places=["red block=0,0", "red block=0.1,0"])


def test_a_place_off_the_table_is_one_error_before_anything_runs(tmp_path: Path, capsys) -> None:
    out = tmp_path / "run"
    code = main(["run", "close the top drawer", "--llm", "replay", "--recordings",
                 str(tmp_path / "none.jsonl"), "--out", str(out), "--place", "blue block=0.5,0"])
    assert code == 2 and not out.exists()
    err = " ".join(capsys.readouterr().err.split())
    assert err.count("error") == 1 and "'blue block=0.5,0'" in err and "[-0.675, 0.275]" in err


def test_the_scene_record_says_what_was_set_where_and_why() -> None:
    request = SceneRequest.from_options(["middle"], ["green block=0.0,-0.2", "red line=0.0,0.1"])
    choice = choose_scene("push the blue block onto the red line", np.random.default_rng(4),
                          request)
    placement = sample_placement(choice.layout, np.random.default_rng(4), WorldConfig())
    scene = json.loads(json.dumps(choice.describe(placement)))
    blocks = {b["name"]: b for b in scene["blocks"]}
    assert blocks["blue block"]["why"] == NAMED and blocks["green block"]["why"] == "--place"
    assert blocks["green block"]["xy_m"] == [0.0, -0.2]
    assert blocks["blue block"]["xy_m"] == pytest.approx(list(placement.blocks["blue"][:2]),
                                                         abs=1e-4)
    assert set(blocks) == {f"{c} block" for c in placement.blocks}
    assert {b["why"] for n, b in blocks.items() if n not in ("blue block", "green block")} \
        == {"distractor"}
    (line,) = [x for x in scene["lines"] if x["name"] == "red line"]
    assert line["why"] == f"{NAMED}; --place" and line["xy_m"] == [0.0, 0.1]
    drawers = {d["drawer"]: d for d in scene["drawers"]}
    assert drawers["middle"] == {"drawer": "middle", "opening_m": CLOSE_OPENING_M,
                                 "why": "--drawer-open"}
    assert drawers["top"]["opening_m"] == 0.0 and scene["cabinet"] is True


def test_voxposer_run_writes_the_scene_into_the_summary(tmp_path: Path) -> None:
    out = tmp_path / "run"  # no recordings: the run stops after the reset, with its scene
    code = main(["run", "close the bottommost drawer", "--llm", "replay", "--recordings",
                 str(tmp_path / "none.jsonl"), "--out", str(out), "--no-video",
                 "--place", "blue block=0.0,-0.2"])
    summary = json.loads((out / "summary.json").read_text())
    assert code == 1 and "does not exist" in summary["message"]
    drawers = {d["drawer"]: d for d in summary["scene"]["drawers"]}
    assert drawers["bottom"]["opening_m"] == CLOSE_OPENING_M
    assert drawers["bottom"]["why"] == ASKED_CLOSE
    (blue,) = [b for b in summary["scene"]["blocks"] if b["name"] == "blue block"]
    assert blue["why"] == "--place" and blue["xy_m"] == [0.0, -0.2]


def test_a_place_under_the_cabinet_leaves_the_cabinet_out() -> None:
    rng = np.random.default_rng(0)
    for instruction in ("move to the right side of the table",
                        "push the blue block to the front right corner of the table"):
        scene = choose_scene(instruction, rng)
        assert scene.layout.cabinet is False, instruction
        assert "lies under it" in scene.describe()["cabinet_why"]
    for instruction in ("move to the back right corner of the table",  # clear of the cabinet
                        "close the top drawer", "go to the right side of the cabinet"):
        assert choose_scene(instruction, rng).layout.cabinet is True, instruction
    forced = choose_scene("move to the right side of the table", rng,
                          SceneRequest.from_options(["top"], []))
    assert forced.layout.cabinet is True  # a drawer the options open keeps its cabinet
