"""The report's vague-relational table counts the slots each instruction said otherwise."""

from __future__ import annotations

from voxposer.bench.report_vague import said_otherwise, vague_lines

RECORDS = [
    {"instruction": "push the leftmost block to the back side of the table", "success": True,
     "attributes": {"obj": "pink block", "pos": "back side of the table"}},
    {"instruction": "push the blue block to the back side of the table", "success": False,
     "attributes": {"obj": "blue block", "pos": "back side of the table"}},
    {"instruction": "go to the back side of the table, keeping a hand's width from the block "
                    "nearest the robot", "success": False,
     "attributes": {"obj": "green block", "dist": "9", "pos": "back side of the table"}},
]


def test_a_slot_said_in_its_own_words_is_not_counted() -> None:
    assert said_otherwise(RECORDS[0]) == ("obj",)
    assert said_otherwise(RECORDS[1]) == ()
    assert said_otherwise(RECORDS[2]) == ("obj", "dist")


def test_the_table_splits_each_slots_episodes_and_their_successes() -> None:
    lines = vague_lines(RECORDS)
    assert "| the block by a relation | 2/3 | 1/2 | 1/3 | 0/1 |" in lines
    assert "| a distance vaguely | 1/1 | 0/1 | 0/1 | 0/0 |" in lines
    assert not any("a speed by manner" in line for line in lines)  # no episode had a speed
