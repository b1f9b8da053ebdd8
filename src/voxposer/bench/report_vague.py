"""The vague-relational split in the report: how many episodes said each slot otherwise, and
their success beside the episodes that kept the slot's own words."""

from __future__ import annotations

from typing import Any

#: the slots the split may say otherwise (:mod:`voxposer.bench.vague_relational`).
SLOTS = ("obj", "dist", "velocity", "deixis", "region")
_WHAT = {"obj": "the block by a relation", "dist": "a distance vaguely", "velocity":
         "a speed by manner", "deixis": "the drawer by its state", "region": "a side by the robot"}


def said_otherwise(record: dict[str, Any]) -> tuple[str, ...]:
    """The slots of ``record``'s attributes its instruction does not say in their own words."""
    text, attrs = str(record.get("instruction", "")), record.get("attributes") or {}
    return tuple(s for s in SLOTS if s in attrs and str(attrs[s]) not in text)


def _ok(records: list[dict[str, Any]]) -> int:
    return sum(bool(r.get("success")) for r in records)


def vague_lines(group: list[dict[str, Any]]) -> list[str]:
    """Markdown lines: per slot, the episodes that said it otherwise and their successes, and
    the same for the episodes that said it in its own words."""
    lines = ["| slot | said otherwise | success | in its own words | success |",
             "|---|---|---|---|---|"]
    for slot in SLOTS:
        having = [r for r in group if slot in (r.get("attributes") or {})]
        if not having:
            continue
        other = [r for r in having if slot in said_otherwise(r)]
        own = [r for r in having if r not in other]
        lines.append(f"| {_WHAT[slot]} | {len(other)}/{len(having)} | {_ok(other)}/{len(other)} "
                     f"| {len(own)}/{len(having)} | {_ok(own)}/{len(own)} |")
    return ["", *lines, ""]


__all__ = ["SLOTS", "said_otherwise", "vague_lines"]
