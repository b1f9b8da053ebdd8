"""The vague-relational split: objects named by a relation that singles them out in the
episode's layout, quantities said vaguely but never below what the task checks."""

from __future__ import annotations

import re

import numpy as np
import pytest

from voxposer.bench.attributes import ATTRIBUTES
from voxposer.bench.config import Tolerances
from voxposer.bench.episode import EpisodeJob, run_episode
from voxposer.bench.paraphrases import PARAPHRASES
from voxposer.bench.runner import BenchConfig
from voxposer.bench.vague_relational import (
    DISTANCES,
    REGIONS,
    RELATION_MARGIN_M,
    VELOCITIES,
    block_reference,
    render,
    scene_blocks,
)
from voxposer.errors import ConfigError
from voxposer.lmp.backends.replay import ReplayBackend
from voxposer.lmp.speed_words import speed_factor

BASE, HAND = np.array([-0.60, 0.0, 0.0]), np.array([-0.25, 0.0, 0.4])
ROBOT = (BASE, HAND)


def options(name: str, blocks: dict, split: str, robot: tuple = ROBOT) -> set[str | None]:
    """Every reference ``block_reference`` may pick for ``name``."""
    return {block_reference(name, blocks, split, np.random.default_rng(s), robot)  # type: ignore[arg-type]
            for s in range(30)}


def test_a_block_alone_in_a_relation_is_named_by_it() -> None:
    blocks = {"pink block": np.array([-0.45, 0.0]), "green block": np.array([0.0, -0.25]),
              "blue block": np.array([0.1, 0.25]), "yellow block": np.array([0.05, -0.14])}
    # the pink block: nearest both the base and the hand; third across the table from the
    # left, second from the right, 14 cm and more from its neighbours across it
    assert options("pink block", blocks, "dev") == {
        "the block nearest the robot", "the third block from the left",
        "the second block from the right"}
    # the green block: alone on the left, and the yellow block's neighbour (12 cm apart)
    assert options("green block", blocks, "test") == {
        "the block farthest to the left", "the block closest to the yellow block"}
    # the blue block: no block within 15 cm of it, so never "next to" one
    assert options("blue block", blocks, "dev") == {"the rightmost block",
                                                    "the block farthest from the robot"}


def test_no_relation_within_the_margin_names_nothing() -> None:
    """Two blocks side by side, closer than the margin across the table and equally far from
    the robot: no relation singles either out, so the colour name must stay."""
    gap = RELATION_MARGIN_M * 0.8
    blocks = {"pink block": np.array([-0.3, -gap / 2]), "green block": np.array([-0.3, gap / 2])}
    assert options("pink block", blocks, "dev") == {None}
    # the hand sits over the pink block: closest to the base is not closest to the hand
    blocks = {"pink block": np.array([-0.35, 0.0]), "green block": np.array([0.0, 0.0])}
    hand_over_green = (BASE, np.array([0.0, 0.0, 0.3]))
    assert "the block nearest the robot" not in options("pink block", blocks, "dev", hand_over_green)


def test_vague_quantities_never_ask_less_than_the_check() -> None:
    """Each distance word reads as at least the checked value (inches × 2.54); each speed
    word is said for a band of the same direction (faster ≥ 1.25×, a quarter ≤ 0.4×)."""
    inches = {"an inch and a half": 1.5, "roughly two inches": 2, "two and a half inches": 2.5,
              "roughly three inches": 3, "about four inches": 4, "four inches": 4,
              "four and a half inches": 4.5}
    for cm, words in DISTANCES.items():
        for said in words["test"]:
            if said in inches:
                assert inches[said] * 2.54 >= float(cm) - 0.5, said
    bands = Tolerances().velocity_bands
    for velocity, words in VELOCITIES.items():
        lo = bands[velocity][0]
        for said in words["dev"] + words["test"]:
            factor = speed_factor(said)  # None: no speed word the project reads
            assert factor is None or (factor > 1.0) == (lo > 1.0), (velocity, said)
    assert set(DISTANCES) == set(ATTRIBUTES["dist"]["seen"] + ATTRIBUTES["dist"]["unseen"])


@pytest.mark.parametrize("task", list(PARAPHRASES))
def test_every_task_says_a_slot_otherwise_and_keeps_its_values(task: str) -> None:
    attrs = {k: v["seen"][0] for k, v in ATTRIBUTES.items()}
    attrs.update(obj="pink block", obstacle="green block", region="back side of the table")
    blocks = {"pink block": np.array([-0.45, 0.0]), "green block": np.array([0.0, -0.25]),
              "blue block": np.array([0.05, 0.25])}
    dev = {render(task, attrs, blocks, ROBOT, "dev", s) for s in range(12)}
    test = {render(task, attrs, blocks, ROBOT, "test", s) for s in range(12)}
    assert all(r.vague_slots for r in dev | test)
    assert not {r.instruction for r in dev} & {r.instruction for r in test}
    for r in dev | test:
        assert "[" not in r.instruction and "the the" not in r.instruction
        for said in (w for d in DISTANCES.values() for ws in d.values() for w in ws):
            assert not re.search(re.escape(said) + r"\s?(?:cm|centimet)", r.instruction)
        if "obj" in r.vague_slots:
            assert "pink block" not in r.instruction  # referred to by relation only


def test_reference_programs_cannot_answer_vague_instructions() -> None:
    with pytest.raises(ConfigError, match="vague-relational"):
        BenchConfig(llm="reference", instructions="vague-relational")


def test_an_episode_names_its_block_by_a_relation_of_its_layout(world) -> None:
    job = EpisodeJob("push_to_pos", "seen", 0, llm="replay", instructions="vague-relational",
                     seed_set="dev")
    rec = run_episode(job, world, backend=ReplayBackend([]))  # no recording: the LLM refuses
    blocks, robot = scene_blocks(world)  # nothing moved: the LLM refused the first call
    expected = render("push_to_pos", rec.attributes, blocks, robot, "dev", 0)
    assert rec.instruction == expected.instruction and "obj" in expected.vague_slots
    assert rec.attributes["obj"] not in rec.instruction


def test_an_ordinal_needs_a_clear_gap_on_both_sides() -> None:
    y = {"pink block": -0.3, "green block": -0.1, "blue block": 0.1, "brown block": 0.3}
    blocks = {n: np.array([-0.1 + 0.04 * k, v]) for k, (n, v) in enumerate(y.items())}
    robot = (BASE, np.array([0.5, 0.0, 0.4]))  # nothing singled out by distance to the robot
    assert "the second block from the left" in options("green block", blocks, "dev", robot)
    assert "the third block from the left" in options("blue block", blocks, "dev", robot)
    blocks["blue block"] = np.array([0.0, -0.1 + RELATION_MARGIN_M / 2])  # crowds the green one
    assert not {o for o in options("green block", blocks, "dev", robot) if o and "second" in o}


def test_a_region_said_by_the_robot_is_the_side_the_check_judges() -> None:
    """The API reads "the side of the table nearest the robot" as the back side (the robot
    stands at the back), the same point as the region's own words."""
    from voxposer.lmp import make_tabletop_scene
    from voxposer.lmp.api import LMPAPI

    api = LMPAPI(make_tabletop_scene())
    table = api.detect("table")
    for region, words in REGIONS.items():
        side = region.removesuffix(" of the table")
        for said in words["dev"] + words["test"]:
            assert np.array_equal(api.point_on(table, said), api.point_on(table, side)), said
