"""Helpers the task declarations share: layouts, keep-clear paths, common program pieces."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from voxposer.bench.programs import Programs, affordance_at_place
from voxposer.envs.layout import SceneLayout
from voxposer.places import Place

#: Distractor counts of block tasks (the paper randomises "a number of objects" per task).
DISTRACTOR_BLOCKS = (2, 4)
DISTRACTOR_LINES = (1, 3)


def colour(name: str) -> str:
    """"blue block" → "blue"."""
    return name.split()[0]


def block_layout(poses: Mapping[str, tuple[float, ...]], *, cabinet: bool = False,
                 extra_blocks: tuple[int, int] = DISTRACTOR_BLOCKS,
                 extra_lines: tuple[int, int] = DISTRACTOR_LINES,
                 drawer_openings: Mapping[str, float] | None = None,
                 ee_start: tuple[float, float, float] | None = None,
                 ee_start_yaw: float = 0.0) -> SceneLayout:
    """A layout with the hand-placed ``poses`` ("blue block" → (x, y)) plus distractors (and
    the end effector's start position [m], None: the rest pose, and yaw [rad])."""
    return SceneLayout(
        blocks=tuple(colour(n) for n in poses if n.endswith("block")),
        lines=tuple(colour(n) for n in poses if n.endswith("line")),
        extra_blocks=extra_blocks, extra_lines=extra_lines, cabinet=cabinet,
        drawer_openings=dict(drawer_openings or {}), poses=dict(poses), ee_start=ee_start,
        ee_start_yaw=ee_start_yaw)


def segment_clear(a: tuple[float, float], b: tuple[float, float], radius: float,
                  step: float = 0.04) -> list[tuple[tuple[float, float], float]]:
    """Keep-clear discs along the segment a → b [m] (a path a push or a motion needs)."""
    n = max(2, int(np.ceil(np.hypot(b[0] - a[0], b[1] - a[1]) / step)) + 1)
    return [((float(a[0] + t * (b[0] - a[0])), float(a[1] + t * (b[1] - a[1]))), radius)
            for t in np.linspace(0.0, 1.0, n)]


def one_subtask(progs: Programs, instruction: str, subtask: str, *, reset: bool) -> Programs:
    """Planner code: one composer sub-task (then back to the default pose when ``reset``)."""
    lines = [f"composer('{subtask}')"] + (["composer('back to default pose')"] if reset else [])
    progs.add("planner", instruction, *lines)
    if reset:
        progs.add("composer", "back to default pose", "reset_to_default_pose()")
    return progs


def gripper_composer(progs: Programs, subtask: str, maps: Mapping[str, str]) -> Programs:
    """Composer code moving the gripper with the given map queries ("affordance" → query)."""
    lines = ["movable = parse_query_obj('gripper')"]
    for kind, query in maps.items():
        lines.append(f"{kind}_map = get_{kind}_map('{query}')")
    args = ", ".join(f"{k}_map={k}_map" for k in maps)
    lines.append(f"execute(movable, {args})")
    return progs.add("composer", subtask, *lines)


#: Where the end effector starts each episode (the robot's rest pose), x, y [m].
EE_START_XY = (-0.23, 0.0)


def toward(a: tuple[float, float], b: tuple[float, float], r: float,
           lateral: float = 0.0) -> tuple[float, float]:
    """The point ``r`` metres from ``a`` toward ``b`` (shifted ``lateral`` m to its left)."""
    d = np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    u = d / max(float(np.linalg.norm(d)), 1e-9)
    n = np.array([u[1], -u[0]])
    p = np.asarray(a, dtype=float) + r * u + lateral * n
    return float(p[0]), float(p[1])


def place_query(place_name: str, height_cm: float) -> str:
    """The affordance query for a point above a table place."""
    return f"a point {height_cm:g}cm above the {place_name}"


#: Radius [m] kept free of distractors around where the end effector should end.
TARGET_CLEAR_M = 0.09


def clear_at(point: tuple[float, float]) -> list[tuple[tuple[float, float], float]]:
    """``keep_clear`` for a task that ends at ``point``: no distractor within 9 cm of it."""
    return [(point, TARGET_CLEAR_M)]


def move_to_place_programs(instruction: str, subtask: str, place: Place, kind: str | None,
                           query: str = "") -> Programs:
    """Reference programs for one sub-task moving the gripper 5 cm above ``place`` with one more
    map (``kind`` "avoidance"/"velocity", answering ``query``; the caller adds that map's code).
    ``kind=None`` leaves the extra map out: the constraint-blind control."""
    aff = place_query(place.name, 5)
    progs = one_subtask(Programs(), instruction, subtask, reset=False)
    maps = {"affordance": aff} if kind is None else {"affordance": aff, kind: query}
    gripper_composer(progs, subtask, maps)
    return progs.add("get_affordance_map", aff, *affordance_at_place(place, 5))


#: Height of a low start [m]: tasks whose constraint lives on the path start the end effector
#: this high, so that the path to a table place (5 cm up) runs at the blocks' height.
LOW_START_Z = 0.06
#: Box the low start (x, y) is drawn in [m] (reachable top-down at that height).
LOW_START_LO, LOW_START_HI = (-0.42, -0.34), (0.12, 0.34)


def low_path(rng: np.random.Generator, target: tuple[float, float], length: tuple[float, float],
             at: tuple[float, float], lateral: tuple[float, float],
             directions: tuple[tuple[float, float], ...] | None = None
             ) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """A low start and a block on the way to ``target`` (x, y) [m].

    The start lies ``length`` (lo, hi) [m] from the target, in a random horizontal direction
    (or one of ``directions``, unit vectors pointing from the target to the start); the block
    stands ``at`` (lo, hi) [m] from the target along that line, shifted ``lateral`` (lo, hi) [m]
    to the left of the motion (negative: right). Returns (start, block), or None when no start
    inside the reachable box was found.
    """
    t = np.asarray(target, dtype=float)
    for _ in range(100):
        if directions:
            u = np.asarray(directions[int(rng.integers(len(directions)))], dtype=float)
        else:
            angle = float(rng.uniform(0.0, 2.0 * np.pi))
            u = np.array([np.cos(angle), np.sin(angle)])
        start = t + float(rng.uniform(*length)) * u
        if not (np.all(start >= LOW_START_LO) and np.all(start <= LOW_START_HI)):
            continue
        block = toward(tuple(t), tuple(start), float(rng.uniform(*at)),
                       -float(rng.uniform(min(lateral), max(lateral))))
        return (float(start[0]), float(start[1])), block
    return None


def start_above(xy: tuple[float, float], z: float = LOW_START_Z) -> tuple[float, float, float]:
    """The low start pose's position ``z`` [m] above ``xy`` [m]."""
    return (float(xy[0]), float(xy[1]), float(z))


def path_clear(world: Any, target: tuple[float, float]) -> list[tuple[tuple[float, float], float]]:
    """``keep_clear`` for a task that moves the end effector from where it starts to ``target``:
    no distractor within 9 cm of the target or 7 cm of the straight way there."""
    ee = world.get_ee_pose()[0]
    return clear_at(target) + segment_clear((float(ee[0]), float(ee[1])), target, 0.07)
