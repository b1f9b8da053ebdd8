"""An object description cut short on its way to ``parse_query_obj``, made whole again.

A composer or map program often passes only the head of a relational description: the query
"the left of the third block from the right" becomes ``parse_query_obj('third block')``, and
the model then guesses which block that is. :func:`whole_description` finds those words in the
calling program's own query and gives back the relational tail that follows them there ("from
the right", "counting from the left", "nearest the robot", "next to the blue block"); words that
name a scene object, or that the calling query does not continue, are left as they are.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Final

from voxposer.perception.names import normalize_name

#: the relational tails a description may continue with.
_TAIL: Final = re.compile(
    r"\s+(?:(?:counting\s+)?from\s+the\s+(?:left|right|front|back|robot)\b|"
    r"(?:nearest|closest|next|furthest|farthest|closer|further)\s+(?:to\s+|from\s+)?the\s+"
    r"(?:robot|[a-z]+\s+(?:block|line|drawer|cabinet))\b)")


def whole_description(words: str, context: str, objects: Sequence[str]) -> str:
    """``words`` with the relational tail ``context`` continues them with, if any (module
    docs); ``words`` unchanged when they name one of ``objects`` or ``context`` adds none."""
    key = normalize_name(words)
    if not key or any(normalize_name(o) == key for o in objects):
        return words
    text = " ".join(str(context).lower().split())
    for m in re.finditer(rf"\b{re.escape(' '.join(str(words).lower().split()))}\b", text):
        if tail := _TAIL.match(text, m.end()):
            return f"{words}{tail.group(0)}"
    return words


__all__ = ["whole_description"]
