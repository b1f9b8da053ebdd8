"""Reference programs for opening the door, the window and the fridge (no LLM).

Hand-written with the same API the model uses (planner → composer → value-map LMPs), served by
the replay backend (a test double of an LLM that answers each (LMP, query) with fixed code). They
are what a careful programmer writes zero-shot from the instruction alone: grasp the handle,
press the door's lever down first, pull along the handle's normal or slide the sash. They know
nothing of the hinge's arc, the latch's angle or the seal's force: the zero-shot trajectories
they give are the exploration prior, not a solution.
"""

from __future__ import annotations

import re
from typing import Any, Final

from voxposer.errors import ConfigError
from voxposer.lmp.backends.replay import ReplayBackend

#: The instruction of each articulated task.
INSTRUCTIONS: Final = {"door": "open the door", "window": "open the window",
                       "fridge": "open the fridge"}

_GRASP = """movable = parse_query_obj('gripper')
affordance_map = get_affordance_map('the center of the {h}')
rotation_map = get_rotation_map('face the {h} from above')
gripper_map = get_gripper_map('open everywhere except 1cm around the {h}')
execute(movable, affordance_map=affordance_map, rotation_map=rotation_map, gripper_map=gripper_map)"""
_MOVE_HELD = """movable = parse_query_obj('gripper')
affordance_map = get_affordance_map('{target}')
rotation_map = get_rotation_map('face the {h} from above')
gripper_map = get_gripper_map('close everywhere')
execute(movable, affordance_map=affordance_map, rotation_map=rotation_map, gripper_map=gripper_map)"""
_RELEASE = """movable = parse_query_obj('gripper')
affordance_map = get_affordance_map('the center of the gripper')
gripper_map = get_gripper_map('open everywhere')
execute(movable, affordance_map=affordance_map, gripper_map=gripper_map)"""

#: task → (handle, the part whose front the hand faces, how steeply it comes from above (the
#: approach's downward component against its horizontal one), [(sub-task, affordance query,
#: affordance code)] of the moves made holding the handle).
_MOVES: Final[dict[str, tuple[str, str, float, list[tuple[str, str, str]]]]] = {
    "door": ("door handle", "door", 1.0, [
        ("press the door handle down by 3cm", "a point 3cm below the door handle",
         "x, y, z = handle.position + cm2index(3, 'down')"),
        ("pull the door handle 25cm back", "a point 25cm away from the door handle along the "
         "normal of the door", "x, y, z = handle.position + cm2index(25, front.normal)"),
    ]),
    "window": ("window handle", "window", 1.7, [
        ("slide the window handle 20cm to the left", "a point 20cm to the left of the window "
         "handle", "x, y, z = handle.position + cm2index(20, 'left')"),
    ]),
    "fridge": ("fridge handle", "fridge door", 1.0, [
        ("pull the fridge handle 25cm back", "a point 25cm away from the fridge handle along "
         "the normal of the fridge door", "x, y, z = handle.position + cm2index(25, front.normal)"),
    ]),
}


def reference_entries(task: str) -> list[dict[str, Any]]:
    """Replay entries answering every LMP query of ``task``'s reference program."""
    if task not in _MOVES:
        raise ConfigError(f"no reference program for task {task!r}; tasks: {', '.join(_MOVES)}")
    handle, front, steep, moves = _MOVES[task]
    # a bar across the door is gripped across it; the window's knob with the fingers along y
    fingers = "[-front.normal[0], -front.normal[1], 0]" if task != "window" else "None"
    code: dict[tuple[str, str], str] = {}
    plan = [f"composer('grasp the {handle}')"]
    plan += [f"composer('{sub}')" for sub, _, _ in moves]
    plan += [f"composer('release the {handle}')"]
    code[("planner", INSTRUCTIONS[task])] = "\n".join(plan)
    code[("composer", f"grasp the {handle}")] = _GRASP.format(h=handle)
    code[("composer", f"release the {handle}")] = _RELEASE
    code[("get_affordance_map", f"the center of the {handle}")] = "\n".join([
        "affordance_map = get_empty_affordance_map()", f"handle = parse_query_obj('{handle}')",
        "x, y, z = handle.position", "affordance_map[x, y, z] = 1", "ret_val = affordance_map"])
    code[("get_rotation_map", f"face the {handle} from above")] = "\n".join([
        "rotation_map = get_empty_rotation_map()", f"front = parse_query_obj('{front}')",
        "rotation_map[:, :, :] = pointat2quat([-front.normal[0], -front.normal[1], "
        f"-{steep}], fingers={fingers})",
        "ret_val = rotation_map"])
    code[("get_gripper_map", f"open everywhere except 1cm around the {handle}")] = "\n".join([
        "gripper_map = get_empty_gripper_map()", f"handle = parse_query_obj('{handle}')",
        "gripper_map[:] = OPEN", "set_voxel_by_radius(gripper_map, handle.position, 1, CLOSED)",
        "ret_val = gripper_map"])
    for state in ("close", "open"):
        code[("get_gripper_map", f"{state} everywhere")] = "\n".join([
            "gripper_map = get_empty_gripper_map()",
            f"gripper_map[:] = {'CLOSED' if state == 'close' else 'OPEN'}",
            "ret_val = gripper_map"])
    code[("get_affordance_map", "the center of the gripper")] = "\n".join([
        "affordance_map = get_empty_affordance_map()", "gripper = parse_query_obj('gripper')",
        "x, y, z = gripper.position", "affordance_map[x, y, z] = 1", "ret_val = affordance_map"])
    for sub, target, point in moves:
        code[("composer", sub)] = _MOVE_HELD.format(target=target, h=handle)
        code[("get_affordance_map", target)] = "\n".join([
            "affordance_map = get_empty_affordance_map()",
            f"handle = parse_query_obj('{handle}')", f"front = parse_query_obj('{front}')", point,
            "affordance_map[x, y, z] = 1",
            "ret_val = affordance_map"])
    entries = [{"lmp": lmp, "query": q, "responses": [c]} for (lmp, q), c in code.items()]
    named = sorted({n for c in code.values() for n in re.findall(r"parse_query_obj\('([^']+)'\)",
                                                                  c)})
    entries += [{"lmp": "parse_query_obj", "query": n, "responses": [f"ret_val = detect('{n}')"]}
                for n in named]
    return entries


def reference_backend(task: str) -> ReplayBackend:
    """The replay backend serving ``task``'s reference program."""
    return ReplayBackend(reference_entries(task), model=f"reference-{task}")


__all__ = ["INSTRUCTIONS", "reference_backend", "reference_entries"]
