"""Reference programs as replay recordings: ``{"lmp", "query", "responses"}`` entries.

:class:`Programs` collects (LMP, query) → code and adds a ``parse_query_obj`` entry for every
object name the code asks for, so a task writes only the interesting programs. The snippets below
are the code fragments shared by tasks (a table place as a voxel, a block-relative point).
"""

from __future__ import annotations

import re
from typing import Any

from voxposer.places import Place

_PARSE = re.compile(r"parse_query_obj\('([^']+)'\)")


class Programs:
    """Hand-written programs keyed by (LMP, query), convertible to replay recordings."""

    def __init__(self) -> None:
        self._code: dict[tuple[str, str], str] = {}

    def add(self, lmp: str, query: str, *lines: str) -> Programs:
        """Record that ``lmp(query)`` answers with ``lines`` (joined by newlines)."""
        self._code[(lmp, query)] = "\n".join(lines)
        return self

    def keys(self) -> list[tuple[str, str]]:
        """Every (LMP, query) recorded, in order."""
        return list(self._code)

    def code(self, lmp: str, query: str) -> str:
        """The code recorded for ``lmp(query)`` (KeyError if none)."""
        return self._code[(lmp, query)]

    def entries(self) -> list[dict[str, Any]]:
        """Replay entries, including ``parse_query_obj`` for every object the code names."""
        out = [{"lmp": lmp, "query": q, "responses": [c]} for (lmp, q), c in self._code.items()]
        named = {n for c in self._code.values() for n in _PARSE.findall(c)}
        for name in sorted(named):
            if ("parse_query_obj", name) not in self._code:
                out.append({"lmp": "parse_query_obj", "query": name,
                            "responses": [f"ret_val = detect('{name}')"]})
        return out


def place_voxel(place: Place, z_line: str) -> list[str]:
    """Lines that set ``x, y, z`` to the voxel of ``place``'s target point; ``z_line`` sets z
    (it may use ``table_top``, the voxel height of the table's surface)."""
    return [
        "table = parse_query_obj('table')",
        "table_top = table.aabb[1][2]",
        f"x, y, _ = point_on(table, '{place.words}')",
        z_line,
    ]


def affordance_at_place(place: Place, height_cm: float) -> list[str]:
    """get_affordance_map code: ``height_cm`` above the table at ``place``'s target point."""
    return [
        "affordance_map = get_empty_affordance_map()",
        *place_voxel(place, f"z = table_top + cm2index({height_cm}, 'z')"),
        "affordance_map[x, y, z] = 1",
        "ret_val = affordance_map",
    ]


def affordance_place_for_block(place: Place, block: str) -> list[str]:
    """get_affordance_map code: ``place``'s target point at the height of ``block``'s centre."""
    return [
        "affordance_map = get_empty_affordance_map()",
        f"block = parse_query_obj('{block}')",
        *place_voxel(place, "z = block.position[2]"),
        "affordance_map[x, y, z] = 1",
        "ret_val = affordance_map",
    ]
