"""Objects named by relation, grounded by geometry before the planner reads the instruction."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.errors import LLMError, ObjectNotVisibleError
from voxposer.lmp import LMPConfig, LMPRuntime, RecordingHandler, Transcript, make_tabletop_scene
from voxposer.lmp.backends.base import LLMRequest, LLMResponse
from voxposer.lmp.references import ground_references

#: blocks (name → centre [m]); left is −y, front +x; the robot stands at the back (−x)
BLOCKS = {"blue block": (-0.30, -0.30, 0.025), "green block": (0.10, 0.00, 0.025),
          "red block": (-0.10, 0.25, 0.025), "yellow line": (0.0, 0.10, 0.0)}
NAMES = (*BLOCKS, "robot", "gripper", "table")
ROBOT = np.array([[-0.6, 0.0, 0.1], [-0.5, 0.0, 0.5]])


def _ground(text: str, blocks=BLOCKS) -> tuple[str, list[str]]:
    out, done = ground_references(text, (*blocks, "robot", "gripper", "table"),
                                  lambda n: np.asarray(blocks[n], dtype=float), lambda: ROBOT)
    return out, [g.name for g in done]


@pytest.mark.parametrize(("said", "meant"), [
    ("slide the leftmost block along the yellow line", "slide the blue block along the yellow line"),
    ("grasp the block nearest the robot", "grasp the blue block"),
    ("grasp the block that is closest to you", "grasp the blue block"),
    ("go above the block farthest from the robot", "go above the green block"),
    ("go to the block farthest to the right, slowly", "go to the red block, slowly"),
    ("push the block next to the green block to the left", "push the red block to the left"),
    ("push the closest block to the red block", "push the green block"),
    ("hover over the second block from the left", "hover over the green block"),
    ("hover over the third block counting from the left side", "hover over the red block"),
    ("The Rightmost Block, please", "the red block, please"),
    ("move over to the side of the table nearest the robot", "move over to the back side of the table"),
    ("push it to the side of the table away from you", "push it to the front side of the table"),
    ("go to the corner of the table closest to the red block", "go to the front right corner of the table"),
])
def test_a_relation_is_replaced_by_the_block_it_singles_out(said: str, meant: str) -> None:
    assert _ground(said)[0] == meant


def test_names_and_other_words_are_left_as_they_are() -> None:
    for text in ("move to the left of the blue block", "push the block to the front",
                 "go to the back left corner of the table", "the nearest block, please"):
        assert _ground(text) == (text, [])


def test_a_relation_two_blocks_share_within_2_cm_leaves_the_words_to_the_model() -> None:
    tied = {**BLOCKS, "red block": (-0.30, -0.29, 0.025)}  # 1 cm right of the blue block
    assert _ground("push the leftmost block", tied) == ("push the leftmost block", [])
    assert _ground("push the rightmost block", tied)[1] == ["green block"]


def test_an_unseen_candidate_leaves_the_words() -> None:
    def locate(name: str) -> np.ndarray:
        if name == "red block":
            raise ObjectNotVisibleError("red block")
        return np.asarray(BLOCKS[name], dtype=float)

    text = "push the leftmost block"
    assert ground_references(text, NAMES, locate, lambda: ROBOT) == (text, [])


class _FirstRequest:
    """A test double of a backend: keeps the requests and answers none."""

    model = "double"

    def __init__(self) -> None:
        self.requests: list[LLMRequest] = []

    def complete(self, request: LLMRequest) -> LLMResponse:
        self.requests.append(request)
        raise LLMError("no model here")


def planner_request(instruction: str, event: str, **config: object) -> tuple[str, list[dict]]:
    """What the planner is asked for ``instruction`` on the box tabletop (the last message)
    and the transcript's ``event`` events, with ``LMPConfig(**config)``."""
    backend, transcript = _FirstRequest(), Transcript()
    rt = LMPRuntime(make_tabletop_scene(), backend, handler=RecordingHandler(),
                    config=LMPConfig(**config), transcript=transcript)
    with pytest.raises(LLMError):
        rt.run(instruction)
    return (backend.requests[0].messages[-1].content,
            [e for e in transcript.events if e["event"] == event])


@pytest.mark.parametrize("ground", [True, False])
def test_the_planner_reads_the_grounded_instruction_and_the_transcript_says_so(ground: bool) -> None:
    scene = make_tabletop_scene()
    ys = {n: scene.detect(n).position[1] for n in scene.object_names if n.endswith("block")}
    leftmost = min(ys, key=ys.__getitem__)
    asked, events = planner_request("push the leftmost block to the front", "reference_grounded",
                                    ground_references=ground)
    if ground:
        assert asked.endswith(f"push the {leftmost} to the front")
        assert [(e["phrase"], e["name"]) for e in events] == [("the leftmost block", leftmost)]
    else:
        assert asked.endswith("push the leftmost block to the front") and not events
