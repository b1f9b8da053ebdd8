"""One synonym table: the phrases the simulator's registry and the programs' API each accepted
before resolve the same way through :func:`match_name`."""

import pytest

from voxposer.catalog import OBJECTS
from voxposer.errors import UnknownObjectError
from voxposer.perception import is_end_effector, match_name, normalize_name
from voxposer.perception.names import leading_name

NAMES = tuple(o.name for o in OBJECTS)


def test_names_are_lenient() -> None:
    assert normalize_name("The Blue  Block") == "blue block"
    assert normalize_name("topmost drawer") == "top drawer"
    assert normalize_name("grey_line") == "gray line"


@pytest.mark.parametrize(("query", "name"), [
    ("topmost drawer", "top drawer"),
    ("bottommost drawer handle", "bottom drawer handle"),
    ("second to the top drawer", "middle drawer"),
    ("top handle", "top drawer handle"),
    ("the handle of the middle drawer", "middle drawer handle"),
    ("drawer cabinet", "cabinet"),
    ("grey cube", "gray block"),
    ("the Red Cube", "red block"),
    ("end effector", "gripper"),
])
def test_every_former_alias_resolves_to_its_object(query: str, name: str) -> None:
    assert match_name(query, NAMES) == name


def test_a_name_that_matches_nothing_lists_the_scene() -> None:
    with pytest.raises(UnknownObjectError, match="blue block") as info:
        match_name("unicorn", ("table", "blue block"))
    assert "unicorn" in str(info.value)


def test_end_effector_names() -> None:
    assert is_end_effector("The Gripper") and is_end_effector("end effector")
    assert not is_end_effector("blue block")


def test_leading_name_is_the_longest_scene_name_the_words_begin_with() -> None:
    names = ("table", "blue block", "top drawer", "top drawer handle")
    assert leading_name("blue block to the left", names) == "blue block"
    assert leading_name("the top drawer handle gently", names) == "top drawer handle"
    assert leading_name("the topmost drawer", names) == "top drawer"  # through the synonyms
    assert leading_name("block that is blue", names) is None
    assert leading_name("bluest block", names) is None


def test_normalising_is_the_same_for_a_name_asked_again_or_given_as_another_type() -> None:
    import numpy as np

    from voxposer.perception.names import normalize_name

    first = normalize_name("The  Grey_Cube")
    assert first == "gray block" and normalize_name("The  Grey_Cube") == first
    assert normalize_name(np.str_("the grey cube")) == first  # numpy strings, as str()
    assert normalize_name(["grey cube"]) == "['gray block']"  # unhashable: normalised as str()
