"""Reference programs of the "LLM + Primitives" baseline (paper App. A.4): the code a correct
LLM writes against ``prompts/llm_primitives.txt``.

The baseline has one LMP, ``llm_primitives``, asked the instruction itself; its code sees only
``detect`` (position and aabb in metres), ``move_to_pos`` (a straight line), ``rotate_by_quat``,
``set_vel``, ``open_gripper``, ``close_gripper`` and ``np`` (:mod:`voxposer.bench.primitives`).
The helpers below return lines of such code (as the prompt's examples write it: positions from
``detect``, a table place as its target point of :mod:`voxposer.places`); a task's
``primitives_reference`` joins them with :func:`primitives_program`.
"""

from __future__ import annotations

from typing import Final

from voxposer.bench.measures import BASE_XY
from voxposer.bench.programs import Programs
from voxposer.places import Place

#: The baseline's LMP (:data:`voxposer.bench.primitives.PRIMITIVES_SPEC`).
LMP: Final = "llm_primitives"
#: Every name the baseline's code may call or read (its API, ``np`` and ``objects``).
API: Final = frozenset({"detect", "move_to_pos", "rotate_by_quat", "set_vel", "open_gripper",
                        "close_gripper", "np", "objects"})
#: Height of the fingertips over a table place a correct program aims for [m].
HOVER_M: Final = 0.05
#: … over a place behind this x [m] (near the base): there straight moves reach top-down no
#: lower than ``BACK_HOVER_M`` (the elbow folds to its limit).
BACK_X_M: Final = -0.35
BACK_HOVER_M: Final = 0.10
#: A grasp comes down from this high above the block [m].
GRASP_ABOVE_M: Final = 0.10
#: Height a held block is carried at [m] (the fingertips; its bottom 2.5 cm lower).
CARRY_M: Final = 0.12
#: How far behind a pushed block's centre the fingertips come down [m] (3.5 cm off its face).
PUSH_BACK_M: Final = 0.06
#: Fingertip centre → block centre when the closed fingers touch its face [m].
CONTACT_M: Final = 0.035
#: A push is retried (the block detected anew) until its centre is this close to the goal [m].
PUSH_DONE_M: Final = 0.02
#: Pushes per goal at most (the first and its corrections).
PUSH_TRIES: Final = 3
#: How high the hand travels between pushes [m] (above the blocks' tops).
LIFT_M: Final = 0.05
#: Speed scale of a push (at full speed the hand, dragged by the block, sometimes tilts onto it).
PUSH_SPEED: Final = 0.5
#: Behind this x [m] the hand cannot come down to the table from above; it comes down this far
#: to the side [m] and slides in at table height.
NEAR_BASE_X: Final = -0.30
SLIDE_M: Final = 0.10
#: A block pushed to a place behind ``BACK_X_M`` aims this much in front of its point [m]: the
#: hand pushing it there stays in front of the base, where it can still reach the table.
BACK_INSET_M: Final = 0.03


def primitives_program(instruction: str, lines: list[str]) -> Programs:
    """The baseline's programs: ``llm_primitives(instruction)`` answers ``lines``."""
    return Programs().add(LMP, instruction, *lines)


def vec(*values: float) -> str:
    """An ``np.array`` literal of ``values`` (metres)."""
    return "np.array([" + ", ".join(f"{float(v):.3f}" for v in values) + "])"


def hover_z(place: Place) -> float:
    """Height [m] of the fingertips over ``place``'s target point."""
    return BACK_HOVER_M if place.point[0] < BACK_X_M else HOVER_M


def place_target(place: Place) -> str:
    """The fingertips' target (x, y, z) [m] over ``place`` as code."""
    return vec(place.point[0], place.point[1], hover_z(place))


def push_goal(place: Place) -> str:
    """Where a block pushed to ``place`` should end, (x, y) [m], as code."""
    x, y = place.point
    return vec(x + BACK_INSET_M if x < BACK_X_M else x, y)


def move_to_place(place: Place) -> list[str]:
    """Code moving the fingertips over ``place``'s target point in a straight line."""
    return [f"move_to_pos({place_target(place)})"]


def push_lines(obj: str, goals: list[str]) -> list[str]:
    """Code pushing ``obj`` through ``goals`` (code expressions of (x, y) points [m]) with the
    closed fingers: for each goal, come down ``PUSH_BACK_M`` behind the block (detected anew),
    push it along the line to the goal at ``PUSH_SPEED``, lift; repeat up to ``PUSH_TRIES``
    times until its centre is within ``PUSH_DONE_M`` of the goal. Behind ``NEAR_BASE_X`` the
    hand comes down ``SLIDE_M`` to the side of that point (away from the robot's base) and
    slides there at table height: near the base it cannot come down from above."""
    return [
        "close_gripper()",
        f"lift = np.array([0.0, 0.0, {LIFT_M}])",
        f"for goal in [{', '.join(goals)}]:",
        f"    for _ in range({PUSH_TRIES}):",
        f"        block = detect('{obj}')",
        "        d = goal - block.position[:2]",
        f"        if np.linalg.norm(d) < {PUSH_DONE_M}:",
        "            break",
        "        u = d / np.linalg.norm(d)",
        "        z = block.position[2]",
        f"        start = np.array([block.position[0] - {PUSH_BACK_M} * u[0], "
        f"block.position[1] - {PUSH_BACK_M} * u[1], z])",
        f"        end = np.array([goal[0] - {CONTACT_M} * u[0], goal[1] - {CONTACT_M} * u[1], z])",
        f"        if start[0] < {NEAR_BASE_X}:",
        "            n = np.array([-u[1], u[0], 0.0])",
        f"            if np.dot(n[:2], start[:2] - {vec(*BASE_XY)}) < 0:",
        "                n = -n",
        f"            move_to_pos(start + {SLIDE_M} * n + lift)",
        f"            move_to_pos(start + {SLIDE_M} * n)",
        "        else:",
        "            move_to_pos(start + lift)",
        "        move_to_pos(start)",
        f"        set_vel({PUSH_SPEED})",
        "        move_to_pos(end)",
        "        set_vel(1.0)",
        "        move_to_pos(end + lift)",
    ]


def grasp_lines(obj: str, speed: float | None = None) -> list[str]:
    """Code grasping ``obj`` top-down, coming down from ``GRASP_ABOVE_M`` above it, and
    lifting it ``CARRY_M`` (approaching at ``speed``, the ``set_vel`` scale, when given; back to
    1 once the fingers close)."""
    approach = [] if speed is None else [f"set_vel({speed:g})"]
    after = [] if speed is None else ["set_vel(1.0)"]
    return [f"block = detect('{obj}')", "open_gripper()", *approach,
            f"move_to_pos(block.position + np.array([0.0, 0.0, {GRASP_ABOVE_M}]))",
            "move_to_pos(block.position)", "close_gripper()", *after,
            f"move_to_pos(block.position + np.array([0.0, 0.0, {CARRY_M}]))"]


def carry_and_drop_lines(place: Place) -> list[str]:
    """Code carrying a held block ``CARRY_M`` above ``place``'s point, lowering it to
    ``HOVER_M`` there (near the base, where the hand cannot go lower, dropping it from the carry
    height) and releasing it, then up again."""
    x, y = place.point
    carry = f"move_to_pos({vec(x, y, CARRY_M)})"
    lower = [] if hover_z(place) > HOVER_M else [f"move_to_pos({place_target(place)})"]
    return [carry, *lower, "open_gripper()", carry]
