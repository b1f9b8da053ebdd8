"""Side words people use map onto the world frame (front +x, back −x, right +y, left −y, up +z);
contradictions and unknown words are errors that list what is accepted."""

import pytest

from voxposer.lmp.sides import (
    CENTRE_WORDS,
    DIRECTION_WORDS,
    FAR_WORDS,
    FILLER_WORDS,
    NEAR_WORDS,
    SideError,
    direction_sign,
    parse_side,
    splits_at_centre,
)

BACK, FRONT, LEFT, RIGHT, UP, DOWN = (0, -1), (0, 1), (1, -1), (1, 1), (2, 1), (2, -1)


def _signs(*pairs: tuple[int, int]) -> dict[int, int]:
    return dict(pairs)


@pytest.mark.parametrize(("phrase", "expected"), [
    ("the far left corner of the table at the back", _signs(BACK, LEFT)),
    ("at its far end", _signs(BACK)),
    ("the rear", _signs(BACK)),
    ("behind", _signs(BACK)),
    ("the near side", _signs(FRONT)),
    ("the near left corner", _signs(FRONT, LEFT)),
    ("back-left", _signs(BACK, LEFT)),
    ("backleft corner", _signs(BACK, LEFT)),
    ("leftmost", _signs(LEFT)),
    ("the right-most edge", _signs(RIGHT)),
    ("left-hand side", _signs(LEFT)),
    ("the far left", _signs(LEFT)),  # emphasis: the left side
    ("a bit to the left", _signs(LEFT)),  # degree words say how far, not where
    ("slightly more to the back", _signs(BACK)),
    ("all the way to the right", _signs(RIGHT)),
    ("the far right corner at the front", _signs(FRONT, RIGHT)),  # emphasis beside "front"
    ("the end nearest to the robot", _signs(BACK)),
    ("next to the robot", _signs(BACK)),
    ("the robot's side", _signs(BACK)),
    ("the side away from the robot", _signs(FRONT)),
    ("furthest from the robot, on the right", _signs(FRONT, RIGHT, UP)),
    ("in front of the robot", _signs(FRONT)),
    ("close to the back", _signs(BACK)),
    ("topmost", _signs(UP)),
    ("bottommost", _signs(DOWN)),
    ("center", {}),
    ("", {}),
    ("+y", _signs(RIGHT)),
    ("-x half", _signs(BACK)),
])
def test_words_people_use_map_onto_the_world_frame(phrase: str, expected: dict) -> None:
    assert parse_side(phrase) == expected


@pytest.mark.parametrize(("phrase", "surface", "on_page"), [
    ("top-left", True, _signs(BACK, LEFT)),
    ("top-left corner", True, _signs(BACK, LEFT)),
    ("upper right corner", True, _signs(BACK, RIGHT)),
    ("lower left", True, _signs(FRONT, LEFT)),
    ("bottom right corner", True, _signs(FRONT, RIGHT)),
    ("topleft", True, _signs(BACK, LEFT)),
    ("top-left", False, _signs(UP, LEFT)),  # beside an object: above and to the left
    ("top front", True, _signs(UP, FRONT)),  # front/back named: top stays up
    ("top", True, _signs(UP)),
    ("on the left side", True, _signs(UP, LEFT)),  # "on" is not a page word
])
def test_top_and_bottom_beside_left_right_read_as_a_page_on_a_surface(
        phrase: str, surface: bool, on_page: dict) -> None:
    assert parse_side(phrase, surface=surface) == on_page


def test_the_objects_own_name_may_appear_but_only_as_a_phrase() -> None:
    assert parse_side("the left side of the blue block", name="blue block") == _signs(LEFT)
    assert parse_side("the top of the top drawer", name="top drawer") == _signs(UP)
    with pytest.raises(SideError, match="'blue'"):
        parse_side("the left side of the blue block", name="green block")


@pytest.mark.parametrize(("phrase", "words"), [
    ("front back", ("'front'", "'back'", "x axis")),
    ("left and right corner", ("'right'", "'left'", "y axis")),
    ("top bottom", ("'top'", "'bottom'", "z axis")),
    ("the rear front corner", ("'front'", "'back'")),
    ("far near corner", ("far", "near")),
    ("near the robot at the front", ("'front'", "'back'")),
    ("far from the back", ("'far'", "robot")),
])
def test_contradictions_stay_errors_that_say_what_clashes(phrase: str, words: tuple) -> None:
    with pytest.raises(SideError) as err:
        parse_side(phrase)
    assert all(w in str(err.value) for w in words), str(err.value)
    assert repr(phrase) in str(err.value) or "name one" in str(err.value)


def test_an_unknown_word_is_named_and_every_accepted_word_is_listed() -> None:
    with pytest.raises(SideError) as err:
        parse_side("the northern corner")
    message = str(err.value)
    assert "'northern'" in message and "'the northern corner'" in message
    accepted = set(DIRECTION_WORDS) | set(FAR_WORDS) | set(NEAR_WORDS) | set(CENTRE_WORDS) \
        | set(FILLER_WORDS)
    missing = {w for w in accepted if w not in message}
    assert not missing, missing
    # every listed word is accepted on its own
    for word in accepted:
        parse_side(word)


def test_single_direction_words_and_centre_splits() -> None:
    assert direction_sign("rear") == BACK and direction_sign("leftmost") == LEFT
    assert direction_sign("back left") is None and direction_sign("far") is None
    assert splits_at_centre("left half") and splits_at_centre("-y")
    assert not splits_at_centre("the far left corner")
