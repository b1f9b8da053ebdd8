"""Benchmark cases for ``lmp_accuracy.py``: (LMP, query) → expected effect, seen/unseen split.

Unseen attributes (paper App. A.5): colours red/orange/purple/cyan/gray, "right of", "back side
of", distances 4/6/8/10 cm, table positions "back right corner"/"front left corner", regions
"left side"/"front side of the table", "slower speed", "3x speed", deixis "bottommost"/"second to
the top". A case is unseen when its query holds any of them. Each case's ``check`` is declarative
(see ``lmp_accuracy.check_case``); expected geometry comes from the fixed tabletop scene.
"""

from __future__ import annotations

from typing import Any

SEEN_COLOURS = ("blue", "green", "yellow", "pink", "brown")
UNSEEN_COLOURS = ("red", "orange", "purple", "cyan", "gray")
COLOURS = SEEN_COLOURS + UNSEEN_COLOURS
SEEN_DIST = (3, 5, 7, 9, 11)
UNSEEN_DIST = (4, 6, 8, 10)
#: table position phrase → axis signs {axis: sign}, and whether it is seen.
POSITIONS = {
    "back left corner of the table": ({0: -1, 1: -1}, True),
    "front right corner of the table": ({0: 1, 1: 1}, True),
    "right side of the table": ({1: 1}, True),
    "back side of the table": ({0: -1}, True),
    "back right corner of the table": ({0: -1, 1: 1}, False),
    "front left corner of the table": ({0: 1, 1: -1}, False),
    "left side of the table": ({1: -1}, False),
    "front side of the table": ({0: 1}, False),
}
SEEN_SPEEDS = {"faster speed": ("gt", 1.0), "a quarter of the speed": ("eq", 0.25)}
UNSEEN_SPEEDS = {"slower speed": ("lt", 1.0), "3x speed": ("eq", 3.0)}


def _d(k: int, seen: bool) -> int:
    pool = SEEN_DIST if seen else UNSEEN_DIST
    return pool[k % len(pool)]


def _case(lmp: str, query: str, seen: bool, check: dict[str, Any]) -> dict[str, Any]:
    return {"lmp": lmp, "query": query, "split": "seen" if seen else "unseen", "check": check}


def parse_cases() -> list[dict[str, Any]]:
    out = []
    for c in COLOURS:
        seen = c in SEEN_COLOURS
        for q in (f"{c} block", f"the {c} cube", f"the {c} colored block"):
            out.append(_case("parse_query_obj", q, seen, {"type": "object", "name": f"{c} block"}))
        for q in (f"{c} line", f"the {c} line on the table"):
            out.append(_case("parse_query_obj", q, seen, {"type": "object", "name": f"{c} line"}))
    for q, name, seen in (("topmost drawer", "top drawer", True),
                          ("the drawer second to the bottom", "middle drawer", True),
                          ("bottommost drawer", "bottom drawer", False),
                          ("the drawer second to the top", "middle drawer", False),
                          ("handle of the topmost drawer", "top drawer handle", True),
                          ("bottommost drawer handle", "bottom drawer handle", False),
                          ("gripper", "gripper", True), ("the table", "table", True),
                          ("cabinet", "cabinet", True), ("the end effector", "gripper", True)):
        out.append(_case("parse_query_obj", q, seen, {"type": "object", "name": name}))
    return out


def affordance_cases() -> list[dict[str, Any]]:
    out = []
    for k, c in enumerate(COLOURS):
        seen = c in SEEN_COLOURS
        obj = f"{c} block"
        for q, side, cm, s in ((f"left of the {obj}", "left", 5, True),
                               (f"right of the {obj}", "right", 5, False),
                               (f"the front side of the {obj}", "front", 5, True),
                               (f"the back side of the {obj}", "back", 5, False),
                               (f"the top of the {obj}", "top", 5, True)):
            out.append(_case("get_affordance_map", q, seen and s,
                             {"type": "beside", "object": obj, "side": side, "cm": cm}))
        d = _d(k, seen)
        out.append(_case("get_affordance_map", f"a point {d}cm above the {obj}", seen,
                         {"type": "beside", "object": obj, "side": "top", "cm": d}))
        # what a grasp aims at: the block's centre itself, not its top face
        out.append(_case("get_affordance_map", f"a point at the center of the {obj}", seen,
                         {"type": "at_object", "object": obj, "strict": True}))
    for pos, (signs, seen) in POSITIONS.items():
        out.append(_case("get_affordance_map", f"the {pos}", seen,
                         {"type": "table_region", "signs": signs}))
    return out


def avoidance_cases() -> list[dict[str, Any]]:
    out = []
    for k, c in enumerate(COLOURS):
        seen = c in SEEN_COLOURS
        obj = f"{c} block"
        d1, d2, d3 = _d(k, seen), _d(k + 1, seen), _d(k + 2, seen)
        for q, name, r in ((f"the {obj}", obj, None), (f"{d1}cm around the {obj}", obj, d1),
                           (f"at least {d2}cm away from the {obj}", obj, d2),
                           (f"the area {d3}cm around the {obj}", obj, d3),
                           (f"the {c} line", f"{c} line", None),
                           (f"{d1}cm around the {c} line", f"{c} line", d1)):
            out.append(_case("get_avoidance_map", q, seen,
                             {"type": "avoid", "object": name, "radius_cm": r}))
    return out


def velocity_cases() -> list[dict[str, Any]]:
    out = []
    speeds = {**{k: (v, True) for k, v in SEEN_SPEEDS.items()},
              **{k: (v, False) for k, v in UNSEEN_SPEEDS.items()}}
    for k, c in enumerate(COLOURS):
        for j, (speed, ((op, value), s_seen)) in enumerate(speeds.items()):
            seen = c in SEEN_COLOURS and s_seen
            d = _d(k + j, seen)
            out.append(_case("get_velocity_map", f"{speed} within {d}cm of the {c} block", seen,
                             {"type": "speed_near", "object": f"{c} block", "radius_cm": d,
                              "op": op, "value": value}))
    regions = {p: v for p, v in POSITIONS.items() if "side" in p}
    for pos, (signs, r_seen) in regions.items():
        for speed, ((op, value), s_seen) in speeds.items():
            out.append(_case("get_velocity_map", f"{speed} in the {pos}", r_seen and s_seen,
                             {"type": "speed_region", "signs": signs, "op": op, "value": value}))
    for speed, ((op, value), s_seen) in speeds.items():
        out.append(_case("get_velocity_map", f"{speed} everywhere", s_seen,
                         {"type": "speed_region", "signs": {}, "op": op, "value": value}))
    return out


def gripper_cases() -> list[dict[str, Any]]:
    out = [_case("get_gripper_map", "close everywhere", True, {"type": "gripper_all", "value": 1}),
           _case("get_gripper_map", "open everywhere", True, {"type": "gripper_all", "value": 0})]
    for k, c in enumerate(COLOURS):
        seen = c in SEEN_COLOURS
        obj = f"{c} block"
        d = _d(k, seen)
        for q, inside, outside, r in (
                (f"open everywhere except 1cm around the {obj}", 1, 0, 1),
                (f"closed everywhere except {d}cm around the {obj}", 0, 1, d),
                (f"close when within {d}cm of the {obj}", 1, None, d),
                (f"open when within {d}cm of the {obj}", 0, None, d),
                (f"open the gripper everywhere except near the {obj}", 1, 0, None),
                (f"close the gripper within {d}cm of the {c} line", 1, None, d)):
            name = f"{c} line" if "line" in q else obj
            out.append(_case("get_gripper_map", q, seen, {"type": "gripper_near", "object": name,
                                                          "inside": inside, "outside": outside,
                                                          "radius_cm": r}))
    return out


def rotation_cases() -> list[dict[str, Any]]:
    out = [_case("get_rotation_map", q, seen, {"type": "approach", "object": None, "axis": axis})
           for q, axis, seen in (("top-down", [0, 0, -1], True),
                                 ("point the gripper forward", [1, 0, 0], True),
                                 ("point the gripper toward +y", [0, 1, 0], True),
                                 ("point the gripper to the right", [0, 1, 0], False),
                                 ("point the gripper backward", [-1, 0, 0], False),
                                 ("point the gripper to the left", [0, -1, 0], True),
                                 ("point the gripper straight down", [0, 0, -1], True))]
    for which, seen in (("top", True), ("middle", True), ("bottom", True), ("topmost", True),
                        ("bottommost", False), ("second to the top", False)):
        out.append(_case("get_rotation_map", f"face the {which} drawer handle", seen,
                         {"type": "approach", "object": None, "axis": [0, 1, 0]}))
    for k, c in enumerate(COLOURS[3:]):
        seen = c in SEEN_COLOURS
        d = _d(k, seen)
        out.append(_case("get_rotation_map", f"top-down within {d}cm of the {c} block", seen,
                         {"type": "approach", "object": f"{c} block", "axis": [0, 0, -1]}))
    return out


def composer_cases() -> list[dict[str, Any]]:
    out = []
    for k, c in enumerate(COLOURS):
        seen = c in SEEN_COLOURS
        obj = f"{c} block"
        if k % 2 == 0:
            side, phrase = ("left", f"the left of the {obj}") if seen else ("right", f"the right of the {obj}")
            out.append(_case("composer", f"move to {phrase}", seen, {
                "type": "composer", "movable": "gripper",
                "maps": {"affordance_map": {"type": "beside", "object": obj, "side": side, "cm": 5}}}))
        else:
            pos = [p for p, (_, s) in POSITIONS.items() if s == seen][k % 4]
            out.append(_case("composer", f"push the {obj} to the {pos}", seen, {
                "type": "composer", "movable": obj,
                "maps": {"affordance_map": {"type": "table_region", "signs": POSITIONS[pos][0]}}}))
    for k, c in enumerate(COLOURS):
        seen = c in SEEN_COLOURS
        pos = [p for p, (_, s) in POSITIONS.items() if s == seen and "corner" in p][k % 2]
        d = _d(k, seen)
        if k % 2 == 0:
            maps = {"affordance_map": {"type": "table_region", "signs": POSITIONS[pos][0]},
                    "avoidance_map": {"type": "avoid", "object": f"{c} block", "radius_cm": d}}
            q = f"move to the {pos} while staying at least {d}cm from the {c} block"
        else:
            speed = "a quarter of the speed" if seen else "slower speed"
            op, value = ("eq", 0.25) if seen else ("lt", 1.0)
            maps = {"affordance_map": {"type": "table_region", "signs": POSITIONS[pos][0]},
                    "velocity_map": {"type": "speed_near", "object": f"{c} block",
                                     "radius_cm": d, "op": op, "value": value}}
            q = f"move to the {pos} while moving at {speed} when within {d}cm of the {c} block"
        out.append(_case("composer", q, seen, {"type": "composer", "movable": "gripper",
                                               "maps": maps}))
    speeds = {True: (("a quarter of the speed", "eq", 0.25), ("faster speed", "gt", 1.0)),
              False: (("slower speed", "lt", 1.0), ("3x speed", "eq", 3.0))}
    for k, c in enumerate(COLOURS):
        seen = c in SEEN_COLOURS
        speed, op, value = speeds[seen][k % 2]
        out.append(_case("composer", f"grasp the {c} block while moving at {speed}", seen, {
            "type": "composer", "movable": "gripper",
            "maps": {"affordance_map": {"type": "at_object", "object": f"{c} block"},
                     "velocity_map": {"type": "speed_region", "signs": {}, "op": op,
                                      "value": value},
                     "gripper_map": {"type": "gripper_near", "object": f"{c} block",
                                     "inside": 1.0, "outside": 0.0, "radius_cm": 1}}}))
        # the hand, or the block it holds (a held object moves with the hand)
        out.append(_case("composer", f"release the {c} block", seen, {
            "type": "composer", "movable": ["gripper", f"{c} block"],
            "maps": {"gripper_map": {"type": "gripper_all", "value": 0.0}}}))
    return out


def all_cases() -> list[dict[str, Any]]:
    """Every case, grouped by LMP."""
    return (parse_cases() + affordance_cases() + avoidance_cases() + velocity_cases()
            + gripper_cases() + rotation_cases() + composer_cases())
