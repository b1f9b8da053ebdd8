"""The post-conditions a correct planner states for each task (intent checks, reference side).

Reference programs (and their constraint-blind controls, whose planner is the same) state these
after the task's last sub-task that is not "back to default pose", so ``--llm reference`` and
``--llm reference-blind`` runs measure how well intent checks agree with the tasks' checks
where the programs are known: a blind control that ignores its constraint should fail them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

from voxposer.bench.attributes import DEIXIS_DRAWER
from voxposer.bench.measures import VELOCITY_SCALE
from voxposer.bench.programs import Programs


def _where(place: str) -> str:
    return place.removesuffix(" of the table")


def _at(entity: str, place: str) -> str:
    return f"on({entity!r}, 'table', {_where(place)!r})"


#: a task's preposition → the side ``passed_on`` names.
PASSING_SIDE: Final = {"left of": "left side", "right of": "right side", "top of": "top",
                       "front side of": "front side", "back side of": "back side"}


def _speed(a: dict[str, str], zone: str = "") -> str:
    return f"speed('gripper', {VELOCITY_SCALE[a['velocity']]:g}{zone})"


def _preposition(a: dict[str, str]) -> str:
    if a["preposition"] == "top of":
        return f"above('gripper', {a['obj']!r})"
    return f"near('gripper', {a['obj']!r}, cm=12)"


#: task → the conditions (Python source) of its post-condition, from the task's attributes.
EXPECTATIONS: Final[dict[str, Callable[[dict[str, str]], list[str]]]] = {
    "move_to_preposition": lambda a: [_preposition(a)],
    "move_to_pos_staying_on_preposition": lambda a: [
        _at("gripper", a["pos"]),
        f"passed_on('gripper', {a['obj']!r}, {PASSING_SIDE[a['preposition']]!r})"],
    "move_to_pos_velocity_near_obj": lambda a: [
        _at("gripper", a["pos"]), _speed(a, f", near={a['obj']!r}, cm={a['dist']}")],
    "close_drawer": lambda a: [f"moved('{DEIXIS_DRAWER[a['deixis']]} drawer', cm=3)"],
    "push_along_line": lambda a: [f"moved({a['obj']!r}, cm=10)",
                                  f"near({a['obj']!r}, {a['line']!r}, cm=4)"],
    "grasp_at_velocity": lambda a: [f"holding({a['obj']!r})", _speed(a)],
    "drop_to_pos": lambda a: [_at(a["obj"], a["pos"])],
    "push_stay_on_region": lambda a: [f"moved({a['obj']!r}, cm=5)", _at(a["obj"], a["region"])],
    "move_to_region": lambda a: [_at("gripper", a["region"])],
    "move_to_pos_min_distance": lambda a: [_at("gripper", a["pos"]),
                                           f"away('gripper', {a['obj']!r}, cm={a['dist']})"],
    "move_to_pos_velocity_in_region": lambda a: [
        _at("gripper", a["pos"]), _speed(a, f", inside={_where(a['region'])!r}")],
    "push_to_pos_avoid_obstacle": lambda a: [_at(a["obj"], a["pos"]),
                                             f"away({a['obj']!r}, {a['obstacle']!r}, cm=4)"],
    "push_to_pos": lambda a: [_at(a["obj"], a["pos"])],
}


def expect_line(task: str, attrs: dict[str, str]) -> str | None:
    """``expect(...)`` of ``task`` for ``attrs`` (None: the task states none)."""
    conditions = EXPECTATIONS.get(task, lambda a: [])(attrs)
    return f"expect({', '.join(conditions)})" if conditions else None


def with_expectation(progs: Programs, task: str, attrs: dict[str, str]) -> Programs:
    """``progs`` with the task's ``expect(...)`` after the planner's last sub-task that is not
    "back to default pose" (unchanged when the task states none or there is no planner)."""
    line = expect_line(task, attrs)
    planner = [key for key in progs.keys() if key[0] == "planner"]
    if line is None or not planner:
        return progs
    for key in planner:
        lines = progs.code(*key).splitlines()
        moves = [i for i, ln in enumerate(lines)
                 if ln.startswith("composer(") and "default pose" not in ln]
        if moves:
            lines.insert(moves[-1] + 1, line)
            progs.add(key[0], key[1], *lines)
    return progs
