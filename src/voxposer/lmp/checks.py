"""Sanity checks on what generated code returns; a failed check triggers self-correction.

Once the prompt is good, a small model's mistakes rarely raise: they produce a map that is
empty, unchanged or out of range. These checks turn such results into errors with a message the
model can act on.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from voxposer.errors import EmptyAffordanceError, ResultError
from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.lmp.checklist import MOVE_AWAY
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.registry import LMPSpec
from voxposer.lmp.speed_words import same_direction, speed_factor
from voxposer.perception.names import is_end_effector, leading_name
from voxposer.valuemaps.maps import check_value_map
from voxposer.valuemaps.voxel_ops import nonzero_voxels

#: Largest velocity scale accepted (the paper's "3x speed" is the largest in its task list).
MAX_SPEED_SCALE = 10.0


def check_result(spec: LMPSpec, namespace: dict[str, Any], grid: VoxelGrid) -> Any:
    """The checked result of ``spec``'s code from its namespace after execution.

    Raises:
        ResultError: missing result, wrong type, or a map failing its sanity check.
        EmptyAffordanceError: an affordance map with no positive voxel.
        InvalidMapError: wrong shape/dtype or NaN values.
    """
    name = spec.result_name
    if name is None:
        return None
    if name not in namespace:
        raise ResultError(f"the code did not assign `{name}`; end it with `{name} = ...`")
    value = namespace[name]
    if spec.role == "object":
        if isinstance(value, ObjectView):
            return value
        if isinstance(value, list | tuple) and value and all(isinstance(v, ObjectView) for v in value):
            return value[0] if len(value) == 1 else list(value)
        raise ResultError(f"`{name}` must be an object returned by detect(...); got "
                          f"{type(value).__name__}")
    return check_map(spec.map_kind or "", value, grid)


def check_map(kind: str, value: Any, grid: VoxelGrid) -> np.ndarray:
    """Validate a value map of ``kind`` (see :func:`check_result`); returns it as float32."""
    if isinstance(value, list | tuple):
        raise ResultError(f"`ret_val` must be the {kind} map array of shape {grid.shape}; got a "
                          f"{type(value).__name__}")
    arr = np.asarray(check_value_map(kind, value, grid), dtype=np.float32)
    if kind == "affordance" and not np.any(arr > 0):
        raise EmptyAffordanceError("the affordance map is empty (no voxel > 0); set the target "
                                   "voxel(s) to 1, e.g. affordance_map[x, y, z] = 1")
    if kind == "avoidance" and not np.any(arr > 0):
        raise ResultError("the avoidance map is unchanged (all zeros); set the voxels to avoid "
                          "to 1, e.g. with set_voxel_by_radius(avoidance_map, obj.position, 10, 1)")
    if kind == "velocity":
        if np.all(arr == 1.0):
            raise ResultError("the velocity map is unchanged (all 1); set the speed scale where "
                              "the query asks for it")
        if np.any(arr <= 0) or np.any(arr > MAX_SPEED_SCALE):
            raise ResultError(f"velocity scales must be in (0, {MAX_SPEED_SCALE}]; got min "
                              f"{arr.min():.3g}, max {arr.max():.3g}")
    if kind == "gripper" and (np.any(arr < 0) or np.any(arr > 1)):
        raise ResultError(f"gripper values must be 0 (open) or 1 (closed); got min "
                          f"{arr.min():.3g}, max {arr.max():.3g}")
    if kind == "rotation":
        norms = np.linalg.norm(arr, axis=-1)
        if np.any(np.abs(norms - 1.0) > 1e-2):
            raise ResultError("the rotation map must hold unit quaternions (x, y, z, w) in every "
                              "voxel, e.g. from pointat2quat(...)")
        arr = arr / norms[..., None]
    return arr


def check_execute_target(movable: Any, affordance: Any) -> None:
    """Refuse an ``execute`` whose entity is already at its target: a movable object (not the
    gripper) whose affordance targets all lie inside its own box, 1 voxel added. That is a small
    model's "grasp the pink block" written with the block as the movable; nothing would move.

    Args:
        movable: the entity (:class:`ObjectView`, voxel ``aabb``), as ``execute`` received it.
        affordance: the evaluated affordance map (grid shape) or None.

    Raises:
        ResultError: naming the entity and what to write instead.
    """
    name = str(getattr(movable, "name", ""))
    aabb = getattr(movable, "aabb", None)
    if affordance is None or aabb is None or is_end_effector(name):
        return
    targets = nonzero_voxels(np.asarray(affordance) > 0)
    lo, hi = np.asarray(aabb[0]) - 1, np.asarray(aabb[1]) + 1
    if len(targets) and bool(np.all((targets >= lo) & (targets <= hi))):
        raise ResultError(
            f"execute(): every affordance target lies inside the {name} itself, the movable "
            f"entity, so nothing would move. The movable is what moves: to grasp or reach the "
            f"{name}, move the gripper (`movable = parse_query_obj('gripper')`, with a gripper "
            f"map to close it there); to move the {name}, target the place it should go")


#: a sub-task that moves the hand to a place ("move to the front side of the pink block").
_HAND_MOTION = re.compile(r"^(?:then\s+|and\s+|first\s+)?(?:(?:move|go|head|travel|get|come)\s+"
                          r"(?:over\s+|back\s+)?(?:to|towards?|above|over|near|next\s+to|into)|"
                          r"hover)\b")
#: a sub-task that pushes an object: the words naming it.
_PUSHED = re.compile(r"^(?:then\s+|and\s+)?(?:push|slide|nudge|shove)\s+(?:the\s+)?"
                     r"(?P<obj>[a-z ]+?)\s*(?:\b(?:to|towards?|along|onto|into|in|so|while|"
                     r"until|by|a|back|forward|left|right|away|across|over)\b|$)")
#: words of fixtures: pushed through a part (the handle) as the examples do.
_FIXTURES = re.compile(r"\b(?:drawer|handle|door|window|fridge|cabinet|lid)s?\b")


def corrected_movable(subtask: str, movable: Any, objects: tuple[str, ...] = ()
                      ) -> tuple[str, str] | None:
    """The entity ``subtask``'s words say moves, when the ``execute`` got another: a hand
    motion ("move to the front side of the pink block") with an object as the movable (the
    object is where the hand goes: pushing it there moves the wrong thing) → the gripper; a
    push of a block ("nudge the gray block to the back") with the gripper as the movable (the
    block would never move) → that block. The 1.5B model, told so, mostly rewrote the same
    movable (dev seeds), so the runtime corrects it instead of asking.

    Args:
        subtask: the composer's query.
        movable: the entity (:class:`ObjectView`), as ``execute`` received it.
        objects: the scene's object names; a pushed object must begin with one of them.

    Returns:
        (the words of the entity that moves, why), or None when the movable fits the words.
    """
    text = " ".join(str(subtask).lower().split())
    name = str(getattr(movable, "name", ""))
    if not name:
        return None
    if (_HAND_MOTION.match(text) or MOVE_AWAY.match(text)) and not is_end_effector(name):
        return "gripper", (f"the sub-task moves the gripper to a place; the {name} is where it "
                           "goes, not what moves")
    pushed = _PUSHED.match(text)
    if pushed and is_end_effector(name) and not _FIXTURES.search(pushed.group("obj")) \
            and not is_end_effector(pushed.group("obj")) \
            and pushed.group("obj").strip() not in {"it", "them", "this", "that", "one"}:
        obj = pushed.group("obj").strip()
        if objects:
            named = leading_name(obj, objects)
            if named is None:
                return None
            obj = named
        return obj, f"the sub-task pushes the {obj}; with the gripper as the movable it would not move"
    return None


def corrected_speed(query: str, velocity: np.ndarray) -> tuple[np.ndarray, str] | None:
    """``velocity`` (a checked velocity map, default 1) with the scales its code set turned
    to the direction ``query``'s words ask, when every one of them goes the other way
    ("faster speed within 5cm of the yellow block" written as 0.5 there): those voxels get the
    words' factor (:func:`~voxposer.lmp.speed_words.speed_factor`: 2 for a bare "faster", 0.25
    for "a quarter of the speed"). None when the map agrees or the words say no speed.

    Returns:
        (the corrected map, why in words), or None.
    """
    factor = speed_factor(query)
    if factor is None or factor == 1.0:
        return None
    set_ = velocity != 1.0
    if not np.any(set_):
        return None
    values = velocity[set_]
    # some scale goes the words' way (faster: the largest above 1; slower: the smallest below)
    if same_direction(float(values.max() if factor > 1.0 else values.min()), factor):
        return None
    fixed = np.where(set_, np.float32(factor), velocity).astype(velocity.dtype)
    return fixed, (f"the query asks {factor:g}x the speed; the map set "
                   f"{', '.join(f'{v:g}' for v in np.unique(values)[:3])} there")
