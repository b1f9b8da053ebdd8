"""Which benchmark task each few-shot example demonstrates (for the "unseen instruction" folds).

The paper's Table 2 "UI" rows run each task with prompts from which every few-shot example that
demonstrates that task has been removed (leave-one-task-out). The examples of a prompt file say
which tasks they demonstrate on their ``### user`` marker line::

    ### user [tasks: push_to_pos]
    ### user [tasks: grasp_at_velocity, drop_to_pos]
    ### user [tasks: none]

**Every example carries a tag**; ``[tasks: none]`` says it demonstrates no task. An untagged
``### user`` line, a tag on a ``### system``/``### assistant`` line, an unknown task name, a
repeated name, ``none`` mixed with names or any other text after the role is a
:class:`~voxposer.errors.ConfigError`. The tag is part of the marker line, so it never reaches
the messages the model sees.

What an example demonstrates (the rule the packaged prompts are tagged by): task T when the
example's query is

1. an instance of T's instruction template (``bench/tasks/*.py``), or a paraphrase with the same
   slots and behaviour ("put the X on the P" for "drop the X to the P"; other attribute values,
   numbers and direction/speed synonyms such as "behind", "near", "-x half" count as the same); or
2. an instance of a query T's reference programs send to this LMP (a composer sub-task, a map or
   object query), with the same tolerance ("a point 9cm above the pink block" is
   move_to_preposition's "a point 5cm above the [obj]").

A query containing a clause the template lacks, or lacking one it has, is not an instance
("grasp the X" is not "grasp the X ... at [velocity]"). Generic building blocks demonstrate no
task even when a reference program uses them: slot-free commands ("back to default pose",
"top-down", "close everywhere") and bare attribute values (an object or place name such as
"blue block" or "the right side of the table"): they carry no instruction's phrasing, and which
attribute values may appear in prompts is what the seen/unseen *attribute* split governs.

This module must not import :mod:`voxposer.bench`; a test checks :data:`TASK_NAMES` against the
benchmark's registry.
"""

from __future__ import annotations

import re
from typing import Final

from voxposer.errors import ConfigError

#: The benchmark's 13 task names (``bench.tasks.TASKS``), in the row order of Table 4.
TASK_NAMES: Final[tuple[str, ...]] = (
    "move_to_preposition",
    "move_to_pos_staying_on_preposition",
    "move_to_pos_velocity_near_obj",
    "close_drawer",
    "push_along_line",
    "grasp_at_velocity",
    "drop_to_pos",
    "push_stay_on_region",
    "move_to_region",
    "move_to_pos_min_distance",
    "move_to_pos_velocity_in_region",
    "push_to_pos_avoid_obstacle",
    "push_to_pos",
)
#: The tag of an example that demonstrates no task.
NONE_TAG: Final = "none"
#: Separates an LMP's name from its fold's held-out task in a prefix id ("composer~push_to_pos").
FOLD_SEPARATOR: Final = "~"

#: A line that looks like a section marker (well-formed or not).
MARKER_LIKE: Final = re.compile(r"^###\s*(?:system|user|assistant)\b.*$", re.MULTILINE)
_MARKER: Final = re.compile(r"### (system|user|assistant)(?: \[tasks: ([^\]]*)\])?")


def check_task(task: str) -> str:
    """``task`` if it is a benchmark task name; raises ConfigError listing the known ones."""
    if task not in TASK_NAMES:
        raise ConfigError(f"unknown task {task!r}; tasks are: {', '.join(TASK_NAMES)}")
    return task


def parse_marker(line: str, where: str) -> tuple[str, frozenset[str]]:
    """(role, tasks) of a section marker line such as ``### user [tasks: push_to_pos]``.

    Args:
        line: the marker line, without its newline.
        where: names the line in error messages ("prompt 'composer' line 12").

    Raises:
        ConfigError: a malformed marker, a user marker without a tag, a tag on a system or
            assistant marker, or a bad tag (see the module doc).
    """
    m = _MARKER.fullmatch(line.rstrip())
    if m is None:
        raise ConfigError(f"{where}: malformed section marker {line!r}; write '### system', "
                          "'### user [tasks: <task>, ...]' (or '[tasks: none]') or "
                          "'### assistant'")
    role, tag = m.group(1), m.group(2)
    if role != "user":
        if tag is not None:
            raise ConfigError(f"{where}: only '### user' lines carry a [tasks: ...] tag; got "
                              f"{line!r}")
        return role, frozenset()
    if tag is None:
        raise ConfigError(f"{where}: every example must say which benchmark tasks it "
                          f"demonstrates: '### user [tasks: <task>, ...]' or '### user [tasks: "
                          f"none]'; got {line!r}")
    return role, parse_tasks(tag, where)


def parse_tasks(tag: str, where: str) -> frozenset[str]:
    """The task names of a tag's body ("push_to_pos, drop_to_pos"; "none" → empty)."""
    names = [n.strip() for n in tag.split(",")]
    if names == [NONE_TAG]:
        return frozenset()
    if any(not n for n in names):
        raise ConfigError(f"{where}: empty task name in [tasks: {tag}]; list task names "
                          "separated by commas, or write [tasks: none]")
    if NONE_TAG in names:
        raise ConfigError(f"{where}: [tasks: {tag}] mixes 'none' with task names")
    if len(set(names)) != len(names):
        raise ConfigError(f"{where}: [tasks: {tag}] names a task twice")
    for n in names:
        if n not in TASK_NAMES:
            raise ConfigError(f"{where}: unknown task {n!r} in [tasks: {tag}]; tasks are: "
                              f"{', '.join(TASK_NAMES)}")
    return frozenset(names)


def fold_prefix_id(lmp: str, held_out_task: str | None) -> str:
    """The prefix id of ``lmp``'s prompt in a fold: ``lmp`` itself, or ``"<lmp>~<task>"``."""
    return lmp if held_out_task is None else f"{lmp}{FOLD_SEPARATOR}{held_out_task}"


def lmp_of(prefix_id: str | None) -> str:
    """The LMP a prefix id belongs to ("composer~push_to_pos" → "composer"; None → "")."""
    return (prefix_id or "").split(FOLD_SEPARATOR, 1)[0]
