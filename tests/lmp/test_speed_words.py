"""Speed words: the factor a phrase asks and where the phrase is."""

from __future__ import annotations

import pytest

from voxposer.lmp.speed_words import same_direction, speed_factor, speed_span


@pytest.mark.parametrize(("text", "factor", "phrase"), [
    ("move at a quarter of the speed in the back side", 0.25, "at a quarter of the speed"),
    ("moving at faster speed in the back side of the table", 2.0, "at faster speed"),
    ("grasp the purple block at 3x speed", 3.0, "at 3x speed"),
    ("move 3 times slower near the block", 1 / 3, "3 times slower"),
    ("go at half speed", 0.5, "at half speed"),
    ("move half as fast", 0.5, "half as fast"),
    ("at twice the speed", 2.0, "at twice the speed"),
    ("go there slowly", 0.5, "slowly"),
    ("as fast as is safe", 2.0, "fast"),
    # a table part's "half" and an object's "top" are not speeds
    ("move to the left half of the table at slower speed", 0.5, "at slower speed"),
    ("move to the top of the blue block at a quarter of the speed", 0.25,
     "at a quarter of the speed"),
])
def test_factor_and_phrase(text: str, factor: float, phrase: str) -> None:
    assert speed_factor(text) == pytest.approx(factor)
    span = speed_span(text)
    assert span is not None and text[span[0]:span[1]] == phrase


@pytest.mark.parametrize("text", ["move to the back side of the table",
                                  "move to the top of the blue block",
                                  "push the block to the left half of the table"])
def test_no_speed_said(text: str) -> None:
    assert speed_factor(text) is None
    assert speed_span(text) is None


def test_direction() -> None:
    assert same_direction(2.0, 3.0) and same_direction(0.25, 0.5) and same_direction(1.0, 1.0)
    assert not same_direction(2.0, 0.25) and not same_direction(1.0, 0.5)
