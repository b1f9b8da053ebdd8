"""The runtime's query forms: an exact name, a stand-in for an absent object."""

from __future__ import annotations

from voxposer.lmp.query_forms import QueryForms
from voxposer.lmp.registry import LMPConfig
from voxposer.lmp.transcript import Transcript

NAMES = ("table", "gripper", "yellow block", "cyan block", "green line")


def forms(**config: object) -> QueryForms:
    return QueryForms(LMPConfig(**config), lambda: NAMES, Transcript())


def test_an_absent_coloured_object_stands_for_the_one_the_calling_query_names() -> None:
    f = forms()
    got = f.stand_in("parse_query_obj", "blue block", "the back side of the yellow block")
    assert got == "yellow block"
    (event,) = [e for e in f.transcript.events if e["event"] == "object_substituted"]
    assert event["query"] == "blue block" and event["name"] == "yellow block"


def test_no_stand_in_when_the_object_exists_is_not_a_plain_name_or_is_ambiguous() -> None:
    f = forms()
    context = "between the yellow block and the cyan block"
    assert f.stand_in("parse_query_obj", "cyan block", "the yellow block") == "cyan block"
    assert f.stand_in("parse_query_obj", "blue block", context) == "blue block"  # two blocks
    assert f.stand_in("parse_query_obj", "leftmost block", "the yellow block") == "leftmost block"
    assert f.stand_in("parse_query_obj", "blue block", "the right side of the table") == "blue block"
    assert f.stand_in("parse_query_obj", "blue line", "the yellow block") == "blue line"  # kind
    assert f.stand_in("get_affordance_map", "blue block", "the yellow block") == "blue block"
    off = forms(object_stand_in=False)
    assert off.stand_in("parse_query_obj", "blue block", "the yellow block") == "blue block"
    assert not [e for e in f.transcript.events if e["event"] == "object_substituted"]


def test_an_exact_name_is_answered_without_the_model() -> None:
    f = forms()
    assert f.exact_code("parse_query_obj", "yellow block") == "ret_val = detect('yellow block')"
    assert f.exact_code("parse_query_obj", "leftmost block") is None
