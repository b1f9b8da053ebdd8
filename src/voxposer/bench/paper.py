"""The paper's simulated results (Table 4 and Table 2), transcribed for side-by-side reports.

Table 4: success rate [%] over 20 episodes per task, "SA" seen and "UA" unseen attributes.
Table 2 aggregates by category and seen/unseen *instructions* (SI/UI) as well as attributes;
this benchmark reproduces the attribute split only, so reports compare per-category means of the
Table 4 rows (:func:`paper_category_means`) and list Table 2's numbers for reference.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Final

#: Table 4 row → method column → (SA, UA) success [%]. Columns: "U-Net + MP", "LLM + Prim.",
#: "VoxPoser". Entries the paper's table leaves blank are None.
TABLE4: Final[dict[str, dict[str, tuple[float | None, float | None]]]] = {
    "move to the [preposition] the [obj]": {
        "U-Net + MP": (95.0, 0.0), "LLM + Prim.": (85.0, 60.0), "VoxPoser": (90.0, 55.0)},
    "move to the [pos] while staying on the [preposition] the [obj]": {
        "U-Net + MP": (100.0, 10.0), "LLM + Prim.": (80.0, 30.0), "VoxPoser": (95.0, 50.0)},
    "move to the [pos] while moving at [velocity] when within [dist]cm from the obj": {
        "U-Net + MP": (None, 0.0), "LLM + Prim.": (10.0, 0.0), "VoxPoser": (100.0, 95.0)},
    "close the [deixis] drawer by pushing": {
        "U-Net + MP": (None, 0.0), "LLM + Prim.": (60.0, 60.0), "VoxPoser": (80.0, 80.0)},
    "push the [obj] along the [line]": {
        "U-Net + MP": (0.0, 0.0), "LLM + Prim.": (0.0, 0.0), "VoxPoser": (65.0, 30.0)},
    "grasp the [obj] from the table at [velocity]": {
        "U-Net + MP": (35.0, 0.0), "LLM + Prim.": (75.0, 70.0), "VoxPoser": (65.0, 40.0)},
    "drop the [obj] to the [pos]": {
        "U-Net + MP": (70.0, 10.0), "LLM + Prim.": (60.0, 100.0), "VoxPoser": (60.0, 100.0)},
    "push the [obj] while letting it stay on [region]": {
        "U-Net + MP": (None, 5.0), "LLM + Prim.": (10.0, 0.0), "VoxPoser": (50.0, 50.0)},
    "move to the [region]": {
        "U-Net + MP": (5.0, 0.0), "LLM + Prim.": (100.0, 95.0), "VoxPoser": (100.0, 100.0)},
    "move to the [pos] while staying at least [dist]cm from the [obj]": {
        "U-Net + MP": (0.0, 0.0), "LLM + Prim.": (15.0, 20.0), "VoxPoser": (85.0, 90.0)},
    "move to the [pos] while moving at [velocity] in the [region]": {
        "U-Net + MP": (0.0, 0.0), "LLM + Prim.": (90.0, 45.0), "VoxPoser": (85.0, 85.0)},
    "push the [obj] to the [pos] while staying away from [obstacle]": {
        "U-Net + MP": (0.0, 0.0), "LLM + Prim.": (0.0, 10.0), "VoxPoser": (45.0, 55.0)},
    "push the [obj] to the [pos]": {
        "U-Net + MP": (0.0, 0.0), "LLM + Prim.": (20.0, 25.0), "VoxPoser": (80.0, 75.0)},
}

#: Table 2: column → (train/test split, category) → success [%].
TABLE2: Final[dict[str, dict[tuple[str, str], float]]] = {
    "U-Net + MP": {("SI SA", "Object Interactions"): 21.0, ("SI SA", "Spatial Composition"): 53.8,
                   ("SI UA", "Object Interactions"): 3.0, ("SI UA", "Spatial Composition"): 3.8,
                   ("UI UA", "Object Interactions"): 0.0, ("UI UA", "Spatial Composition"): 25.0},
    "LLM + Prim.": {("SI SA", "Object Interactions"): 41.0, ("SI SA", "Spatial Composition"): 43.8,
                    ("SI UA", "Object Interactions"): 46.0, ("SI UA", "Spatial Composition"): 25.0,
                    ("UI UA", "Object Interactions"): 17.5, ("UI UA", "Spatial Composition"): 25.0},
    "VoxPoser": {("SI SA", "Object Interactions"): 64.0, ("SI SA", "Spatial Composition"): 77.5,
                 ("SI UA", "Object Interactions"): 60.0, ("SI UA", "Spatial Composition"): 58.8,
                 ("UI UA", "Object Interactions"): 65.0, ("UI UA", "Spatial Composition"): 76.7},
}


def paper_rate(row: str, column: str, split: str) -> float | None:
    """Table 4's success [%] for a row, method column and split ("seen"/"unseen")."""
    pair = TABLE4.get(row, {}).get(column)
    if pair is None:
        return None
    return pair[0 if split == "seen" else 1]


def paper_category_means(rows: Mapping[str, str], column: str) -> dict[tuple[str, str], float]:
    """(category, split) → mean of Table 4's rows of that category; ``rows``: row → category."""
    out: dict[tuple[str, str], float] = {}
    for category in sorted(set(rows.values())):
        for split in ("seen", "unseen"):
            vals = [paper_rate(r, column, split) for r, c in rows.items() if c == category]
            known = [v for v in vals if v is not None]
            if known:
                out[(category, split)] = sum(known) / len(known)
    return out
