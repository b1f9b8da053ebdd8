"""Distances said in words, other units or body measures, said in centimetres for the planner."""

from __future__ import annotations

import pytest

from tests.lmp.test_references import planner_request
from voxposer.lmp.quantities import plain_quantities


@pytest.mark.parametrize(("said", "plain"), [
    ("keep at least a hand's width away from the red block", "keep at least 10.2 cm away from the red block"),
    ("stay roughly two inches from it", "stay roughly 5.1 cm from it"),
    ("three or so centimeters above", "3 cm above"),
    ("an inch and a half", "3.8 cm"),
    ("two and a half inches", "6.4 cm"),  # 6.35 rounded up: a distance to keep stays kept
    ("about a palm's width", "about 7.6 cm"),
    ("a little over ten centimetres", "a little over 10 cm"),
    ("push it a couple of centimetres back", "push it 2 cm back"),
    ("a 2-inch gap", "a 5.1 cm gap"),
    ("half a metre", "50 cm"),
])
def test_a_distance_is_said_in_centimetres(said: str, plain: str) -> None:
    assert plain_quantities(said)[0] == plain


@pytest.mark.parametrize("text", [
    "move 10 cm to the left of the blue block", "5cm above the block", "give me a hand",
    "one in front of the other", "at a quarter of the speed", "the second block from the left",
    "move a bit to the right"])
def test_other_words_and_plain_centimetres_stay(text: str) -> None:
    assert plain_quantities(text) == (text, [])


def test_the_planner_reads_centimetres_and_the_transcript_says_so() -> None:
    asked, events = planner_request("hover two inches above the blue block", "quantity_said_plainly")
    assert asked.endswith("hover 5.1 cm above the blue block")
    assert [(e["said"], e["cm"]) for e in events] == [("two inches", 5.1)]
