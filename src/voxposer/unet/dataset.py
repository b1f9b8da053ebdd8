"""The stored training data of the "U-Net + MP" baseline: sharded arrays and their manifest.

A data folder holds compressed ``shard_NNNNN.npz`` files (the arrays of :data:`ARRAYS`, one row
per sample) beside ``manifest.json`` (format, grid shape, cost scale, encoding, vocabulary, the
shards with their counts, the (task, seed) episodes done or skipped). Written by
:func:`voxposer.bench.unet_data.generate` (``voxposer bench-data``), read by
:func:`load_dataset` (``voxposer train-unet``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final, NamedTuple

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.unet.vocabulary import Vocabulary

MANIFEST: Final = "manifest.json"
FORMAT: Final = 1
#: what each shard array holds (written into the manifest).
ARRAYS: Final[dict[str, str]] = {
    "occupancy": "uint8 (N, X, Y, Z): 1 where the fused point cloud has a point",
    "colour": "uint8 (N, X, Y, Z, 3): mean RGB of the voxel's points, 0 where empty",
    "cost": "float32 (N, X, Y, Z): the planner's cost map of the first sub-task at its first "
            "plan (CostMap.cost), in [0, affordance_weight + avoidance_weight]",
    "instruction": "str (N,): the seen instruction", "task": "str (N,)", "seed": "int64 (N,)",
    "subtask": "str (N,): the first sub-task", "entity": "str (N,): its movable"}


@dataclass(frozen=True)
class Sample:
    """One training triple (shapes on the coarse planning grid (X, Y, Z)).

    Attributes:
        task, seed: the episode. instruction: the seen instruction.
        subtask, entity: the first sub-task and the entity it moves.
        occupancy, colour: the observation (:class:`voxposer.unet.encoding.ObservationVoxels`).
        cost: the planner's cost map, float32, shape (X, Y, Z).
        cost_scale: its maximum possible value (affordance_weight + avoidance_weight).
    """

    task: str
    seed: int
    instruction: str
    subtask: str
    entity: str
    occupancy: NDArray[np.uint8]
    colour: NDArray[np.uint8]
    cost: NDArray[np.float32]
    cost_scale: float


class Dataset(NamedTuple):
    """Every shard of a data folder, concatenated (shapes as in :data:`ARRAYS`)."""

    occupancy: NDArray[np.uint8]
    colour: NDArray[np.uint8]
    cost: NDArray[np.float32]
    instruction: tuple[str, ...]
    task: tuple[str, ...]
    seed: NDArray[np.int64]
    manifest: dict[str, Any]


def read_manifest(folder: Path) -> dict[str, Any] | None:
    """The manifest of ``folder`` (None when there is none)."""
    path = Path(folder) / MANIFEST
    if not path.exists():
        return None
    manifest: dict[str, Any] = json.loads(path.read_text())
    if manifest.get("format") != FORMAT:
        raise ConfigError(f"{path} has format {manifest.get('format')!r}; this version reads "
                          f"format {FORMAT}")
    return manifest


def new_manifest() -> dict[str, Any]:
    return {"format": FORMAT, "grid_shape": None, "cost_scale": None, "split": "seen",
            "instructions": "seen", "target": "first sub-task, first plan: CostMap.cost",
            "encoding": {"observation": "ObservationVoxels on the cost grid", "arrays": ARRAYS},
            "vocabulary": [], "instruction_list": [], "shards": [], "done": {}, "skipped": {}}


def write_shard(folder: Path, manifest: dict[str, Any], samples: list[Sample]) -> None:
    """Write ``samples`` as the next shard (if any) and the manifest (atomically)."""
    if samples:
        name = f"shard_{len(manifest['shards']):05d}.npz"
        np.savez_compressed(
            folder / name,
            occupancy=np.stack([s.occupancy for s in samples]),
            colour=np.stack([s.colour for s in samples]),
            cost=np.stack([s.cost for s in samples]),
            instruction=np.array([s.instruction for s in samples]),
            task=np.array([s.task for s in samples]), seed=np.array([s.seed for s in samples]),
            subtask=np.array([s.subtask for s in samples]),
            entity=np.array([s.entity for s in samples]))
        manifest["shards"].append({"file": name, "count": len(samples)})
        for s in samples:
            manifest["done"].setdefault(s.task, []).append(s.seed)
        texts = sorted({*manifest["instruction_list"], *(s.instruction for s in samples)})
        manifest["instruction_list"] = texts
        manifest["vocabulary"] = list(Vocabulary.build(texts).words)
        samples.clear()
    tmp = folder / (MANIFEST + ".tmp")
    tmp.write_text(json.dumps(manifest, indent=1))
    tmp.replace(folder / MANIFEST)


def check_grid(manifest: dict[str, Any], sample: Sample) -> None:
    shape = list(sample.cost.shape)
    if manifest["grid_shape"] is None:
        manifest["grid_shape"], manifest["cost_scale"] = shape, sample.cost_scale
    elif manifest["grid_shape"] != shape:
        raise ConfigError(f"{sample.task} seed {sample.seed}: cost grid {tuple(shape)} differs "
                          f"from the dataset's {tuple(manifest['grid_shape'])}")


def load_dataset(folder: Path) -> Dataset:
    """Every shard of ``folder`` (ConfigError when it holds no dataset)."""
    manifest = read_manifest(Path(folder))
    if manifest is None or not manifest["shards"]:
        raise ConfigError(f"{folder} holds no dataset ({MANIFEST} with shards); write one with "
                          "voxposer bench-data")
    parts: dict[str, list[Any]] = {k: [] for k in ("occupancy", "colour", "cost", "instruction",
                                                   "task", "seed")}
    for shard in manifest["shards"]:
        with np.load(Path(folder) / shard["file"]) as data:
            for key, values in parts.items():
                values.append(data[key])
    cat = {k: np.concatenate(v) for k, v in parts.items()}
    return Dataset(cat["occupancy"], cat["colour"], cat["cost"].astype(np.float32),
                   tuple(str(s) for s in cat["instruction"]), tuple(str(s) for s in cat["task"]),
                   cat["seed"].astype(np.int64), manifest)


__all__ = ["ARRAYS", "FORMAT", "MANIFEST", "Dataset", "Sample", "check_grid", "load_dataset",
           "new_manifest", "read_manifest", "write_shard"]
