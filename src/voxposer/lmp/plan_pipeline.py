"""The planner's code completed before it runs: every completion, in order, behind its switch.

Each step (:mod:`voxposer.lmp.plan_completion`, :mod:`voxposer.lmp.plan_conditions`) reads
the plan's code (and the instruction, the scene's object names) and returns new code, or None
when the plan needs nothing of it; :func:`complete_plan` runs those the :class:`LMPConfig`
switches on and reports each change (what was added or removed, and why) to ``record`` — the
runtime writes them as ``plan_completed`` transcript events.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final, NamedTuple

from voxposer.lmp.plan_along import push_along_ends
from voxposer.lmp.plan_avoid import fold_avoided
from voxposer.lmp.plan_carry import carry_stated_constraints
from voxposer.lmp.plan_completion import (
    LIFT_SUBTASK,
    carry_stay_on,
    drop_final_reset,
    grasp_before_drop,
    hover_over,
    lift_after_grasp,
)
from voxposer.lmp.plan_conditions import derive_conditions, keep_instruction_speed
from voxposer.lmp.plan_places import named_places_only
from voxposer.lmp.plan_speed_near import speed_near_folded
from voxposer.lmp.plan_zone import zone_not_destination
from voxposer.lmp.registry import LMPConfig

#: (instruction, code, object names) → (new code, what changed in words) or None.
Completion = Callable[[str, str, tuple[str, ...]], "tuple[str, str] | None"]


class Step(NamedTuple):
    """One completion: the :class:`LMPConfig` switch, the function, the event's key for its
    change ("added"/"removed") and why it is made."""

    switch: str
    complete: Completion
    key: str
    why: str


def _listed(out: tuple[str, list[str]] | None) -> tuple[str, str] | None:
    return None if out is None else (out[0], "; ".join(out[1]))


def _fixed(text: str, fn: Callable[..., str | None]) -> Completion:
    """A completion that reports the same words whenever it changes the plan."""
    def run(query: str, code: str, names: tuple[str, ...]) -> tuple[str, str] | None:
        done = fn(query, code, names)
        return None if done is None else (done, text)
    return run


#: the completions, in the order they run.
STEPS: Final[tuple[Step, ...]] = (
    Step("keep_instruction_speed", lambda q, c, _: _listed(keep_instruction_speed(q, c)),
         "added", "a sub-task's speed asked the opposite of the instruction's"),
    Step("carry_stay_on", _fixed("the instruction's staying-on clause", carry_stay_on),
         "added", "no sub-task carried it"),
    Step("fold_avoided", _fixed("the avoidance in the motion it constrains", fold_avoided),
         "added", "a sub-task went to the object the instruction only asks to keep away from"),
    Step("named_places_only", _fixed("the instruction's one table place", named_places_only),
         "added", "a sub-task went to a table place the instruction does not name"),
    Step("zone_not_destination", _fixed("the speed in the zone, said in the motion to the place",
                                        zone_not_destination),
         "added", "a sub-task went to the table part the instruction says a speed in"),
    Step("speed_near_folded", _fixed("the speed near the object, said in the hand's motion",
                                     speed_near_folded),
         "added", "a sub-task said the speed with no motion of its own"),
    Step("carry_stated_constraints", lambda q, c, n: _listed(carry_stated_constraints(q, c, n)),
         "added", "a post-condition kept a distance or speed the sub-task's words did not"),
    Step("hover_over", _fixed("the hover as the hand's motion", hover_over),
         "added", "a sub-task made the object hover"),
    Step("grasp_before_drop", _fixed("grasp, lift and carry before the release",
                                     lambda _q, c, _n: grasp_before_drop(c)),
         "added", "a sub-task drops an object the plan never grasped"),
    Step("push_along_ends", _fixed("the push to the line's near end, then its far end",
                                   lambda _q, c, n: push_along_ends(c, n)),
         "added", "a sub-task pushed along a line in one motion"),
    Step("lift_after_grasp", _fixed(f"composer({LIFT_SUBTASK!r})",
                                    lambda _q, c, _n: lift_after_grasp(c)),
         "added", "the plan ended on a grasp of a free object"),
    Step("drop_final_reset", _fixed(f"composer({LIFT_SUBTASK!r})",
                                    lambda _q, c, _n: drop_final_reset(c)),
         "removed", "it would undo the hand's motion the plan ends on"),
    Step("derived_conditions", lambda _q, c, n: _listed(derive_conditions(c, n)),
         "added", "post-conditions the sub-tasks' words ask"),
)


def complete_plan(instruction: str, code: str, config: LMPConfig, objects: tuple[str, ...],
                  record: Callable[..., None]) -> str:
    """``code`` after every completion ``config`` switches on; ``record(**fields)`` is called
    once per change with the event's key (``added``/``removed``) and ``why``."""
    for step in STEPS:
        if not getattr(config, step.switch):
            continue
        done = step.complete(instruction, code, objects)
        if done is not None:
            code = done[0]
            record(**{step.key: done[1], "why": step.why})
    return code


__all__ = ["STEPS", "Step", "complete_plan"]
