"""A relational description cut short on its way to parse_query_obj is made whole."""

from __future__ import annotations

import pytest

from voxposer.lmp.descriptions import whole_description

OBJECTS = ("table", "robot", "gripper", "blue block", "pink block")


@pytest.mark.parametrize(("words", "context", "whole"), [
    ("third block", "the left of the third block from the right", "third block from the right"),
    ("second block", "push the second block counting from the left to the back side of the table",
     "second block counting from the left"),
    ("block", "a point 9cm above the block nearest the robot", "block nearest the robot"),
    ("block", "the block next to the blue block", "block next to the blue block"),
    # a scene name, a description with no tail, words the context does not hold: unchanged
    ("blue block", "the block next to the blue block", "blue block"),
    ("leftmost block", "the front side of the leftmost block", "leftmost block"),
    ("third block", "the right side of the table", "third block"),
])
def test_only_a_relational_tail_the_context_says_is_added(words: str, context: str,
                                                          whole: str) -> None:
    assert whole_description(words, context, OBJECTS) == whole
