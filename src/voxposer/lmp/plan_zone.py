"""A speed zone planned as a place to go, folded back into the motion it constrains.

"move over to the back left corner of the table, and over the back side of the table change your
speed to faster speed" was planned (dev records, an extra dev phrasing, ad-hoc seeds 27 and 33)
as ``composer('move to the back left corner of the table')`` then ``composer('move to the back
side of the table while moving at faster speed')``: the table part the speed applies in read as
a second destination. The hand ended 19 cm from the corner, at the default speed through the
zone. :func:`zone_not_destination` mends it without asking: when the instruction says a speed
in one table part ("over the back side of the table") and names one other table place, a
motion to that part which says a speed is dropped, and the motion to the other place says the
speed in the part instead ("… at faster speed in the back side of the table"), as the
composer's examples do. Only plain plans (``composer`` and ``expect`` statements); the dropped
sub-task's post-conditions go with it (they spoke of the wrong place).
"""

from __future__ import annotations

from voxposer.lmp.checklist import HAND_MOTION, REGION_SAID, says_speed
from voxposer.lmp.plan_review import plain_steps
from voxposer.lmp.speed_words import speed_factor, speed_span
from voxposer.lmp.unasked import named_places


def zone_not_destination(instruction: str, code: str, names: tuple[str, ...] = ()
                         ) -> str | None:
    """``code`` with a motion to the instruction's speed zone folded into its motion to the
    place (module docs); None when there is nothing to mend."""
    del names  # the instruction names the zone and the place
    said = " ".join(instruction.lower().split())
    zone = REGION_SAID.search(said)
    steps = plain_steps(code)
    if zone is None or speed_factor(said) is None or steps is None:
        return None
    part = f"{zone.group(1)} of the table"
    if len(named_places(said) - {part}) != 1:
        return None
    to_zone = [i for i, (s, _, _) in enumerate(steps)
               if HAND_MOTION.match(s) and named_places(s) == {part} and says_speed(s)]
    to_place = [i for i, (s, _, _) in enumerate(steps)
                if HAND_MOTION.match(s) and named_places(s) - {part} and not says_speed(s)]
    if len(to_zone) != 1 or len(to_place) != 1:
        return None
    zone_words = steps[to_zone[0]][0]
    span = speed_span(zone_words)
    if span is None:
        return None
    phrase = zone_words[span[0]:span[1]].strip().removeprefix("at ")
    lines: list[str] = []
    for i, (subtask, line, expects) in enumerate(steps):
        if i == to_zone[0]:
            continue
        if i == to_place[0]:
            line = f"composer({subtask.rstrip(' .') + f' at {phrase} in the {part}'!r})"
        lines += [line, *expects]
    return "\n".join(lines)


__all__ = ["zone_not_destination"]
