"""A plan kept to the one table place its instruction names, and a motion repeated with its
constraint said once.

"push the pink block to the right side of the table and keep it away from the blue block" was
planned (dev records of reworded staying-away pushes) as a push to the right side, then "push
the pink block to the back side of the table while staying away from the blue block": a place
the instruction never names, kept when the model was asked to fix it (the review's
:data:`voxposer.lmp.unasked.UNNAMED_PLACE`). :func:`named_places_only` mends it without asking:

- when the instruction names exactly one table place in the places' own words, a sub-task that
  names another place names that one instead;
- a sub-task whose words then begin the next sub-task's words ("push the pink block to the
  right side of the table", then the same "… while staying away from the blue block") is the
  same motion said twice: the first is dropped, its post-conditions kept after the second.

Only plain plans (``composer`` and ``expect`` statements).
"""

from __future__ import annotations

from voxposer.lmp.plan_review import plain_steps
from voxposer.lmp.unasked import named_places


def named_places_only(instruction: str, code: str, names: tuple[str, ...] = ()) -> str | None:
    """``code`` with its table places the one ``instruction`` names and each motion said once;
    None when there is nothing to mend."""
    del names  # the instruction names the place
    steps = plain_steps(code)
    said = named_places(instruction)
    if steps is None or len(said) != 1:
        return None
    (place,) = said
    texts = []
    for subtask, _, _ in steps:
        for other in named_places(subtask) - said:
            subtask = subtask.lower().replace(other, place)
        texts.append(subtask)
    lines: list[str] = []
    carried: list[str] = []
    for i, (text, (_, _, expects)) in enumerate(zip(texts, steps, strict=True)):
        following = texts[i + 1] if i + 1 < len(texts) else ""
        if following.startswith(text.rstrip(" .") + " "):
            carried += expects
            continue
        lines += [f"composer({text!r})", *dict.fromkeys([*carried, *expects])]
        carried = []
    mended = "\n".join(lines)
    unchanged = "\n".join(line for s in steps for line in (f"composer({s[0]!r})", *s[2]))
    return None if mended == unchanged else mended


__all__ = ["named_places_only"]
