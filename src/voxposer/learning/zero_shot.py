"""A recorded zero-shot trajectory τ₀ and the value maps it was planned on (paper Sec. 3.4).

VoxPoser's zero-shot run of an instruction leaves, per executed sub-task, the entity it moved and
the cost map the planner composed from the sub-task's value maps (:class:`Stage`), and the
end-effector's motion over the whole run, resampled at the action period into waypoints
(:class:`ZeroShotTrajectory`). The trajectory is the exploration prior of online dynamics
learning; the stages are its task cost (:mod:`voxposer.learning.task_cost`).

Stored one ``.npz`` per trajectory (:meth:`ZeroShotTrajectory.save`), named by its source and
seed, so that ``k`` trajectories are ``k`` files in one folder.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError
from voxposer.geometry.voxel_grid import VoxelGrid


@dataclass(frozen=True)
class Stage:
    """One executed sub-task of a zero-shot program.

    Attributes:
        subtask: its words ("pull the door handle back by 20cm").
        entity: what the sub-task moved: "gripper" or a part of the scene ("door handle").
        grid: the planning grid of ``cost`` (coarse voxels).
        cost: the composed cost the planner searched, shape ``grid.shape``, float32 (low = good).
        target_distance: distance to the sub-task's affordance target [coarse voxels], shape
            ``grid.shape``, float32.
        gripper: the gripper command while the sub-task ran (1 closed, 0 open).
        reached: whether the zero-shot executor reached the target.
    """

    subtask: str
    entity: str
    grid: VoxelGrid
    cost: NDArray[np.float32]
    target_distance: NDArray[np.float32]
    gripper: float
    reached: bool

    def lookup(self, points: NDArray[np.float64]) -> tuple[NDArray[np.float32],
                                                          NDArray[np.float32]]:
        """(cost, target distance [m]) at ``points`` [m], shape (..., 3), nearest voxel; points
        off the grid take the value of the nearest border voxel."""
        vox = self.grid.world_to_voxel(np.asarray(points).reshape(-1, 3), clip=True)
        i, j, k = vox[:, 0], vox[:, 1], vox[:, 2]
        shape = np.asarray(points).shape[:-1]
        metres = self.target_distance[i, j, k] * np.float32(self.grid.resolution.min())
        return self.cost[i, j, k].reshape(shape), metres.reshape(shape)


@dataclass(frozen=True)
class ZeroShotTrajectory:
    """τ₀: the end-effector's waypoints of one zero-shot run, one per action period.

    Attributes:
        task: the articulated task ("door", "window", "fridge").
        source: what wrote the programs ("reference" or the model's name).
        seed: the episode seed of the run.
        waypoints: end-effector positions [m], shape (T, 3), T >= 2.
        quats: end-effector orientations (x, y, z, w), shape (T, 4).
        gripper: gripper command at each waypoint (1 closed, 0 open), shape (T,).
        stage_of: index into ``stages`` of the sub-task running at each waypoint, shape (T,).
        period_s: simulated time between waypoints [s].
        success: whether the zero-shot run opened the object (the task's own check).
        stages: the executed sub-tasks with their cost maps.
        handle_start: the handle's position [m], shape (3,), as observed at the run's start
            (perception, as in o_0); the waypoints and cost maps are anchored to it. None for
            trajectories recorded without it (then nothing is re-anchored).
    """

    task: str
    source: str
    seed: int
    waypoints: NDArray[np.float64]
    quats: NDArray[np.float64]
    gripper: NDArray[np.float64]
    stage_of: NDArray[np.int64]
    period_s: float
    success: bool
    stages: tuple[Stage, ...]
    handle_start: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        t = len(self.waypoints)
        if t < 2 or self.waypoints.shape != (t, 3):
            raise ConfigError(f"a zero-shot trajectory needs waypoints of shape (T>=2, 3), got "
                              f"{self.waypoints.shape}")
        for name in ("quats", "gripper", "stage_of"):
            if len(getattr(self, name)) != t:
                raise ConfigError(f"zero-shot {name} has {len(getattr(self, name))} rows for "
                                  f"{t} waypoints")
        if not self.stages:
            raise ConfigError("a zero-shot trajectory needs at least one executed sub-task")

    @property
    def prior_actions(self) -> NDArray[np.float64]:
        """The trajectory as actions: waypoint deltas [m] and the next gripper command, shape
        (T - 1, 4)."""
        deltas = np.diff(self.waypoints, axis=0)
        return np.column_stack([deltas, self.gripper[1:]])

    def filename(self) -> str:
        """``<source>-<seed>.npz``."""
        return f"{self.source.replace('/', '_')}-{self.seed}.npz"

    def save(self, folder: Path) -> Path:
        """Write to ``folder/<source>-<seed>.npz`` and return the path."""
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / self.filename()
        meta = {"task": self.task, "source": self.source, "seed": self.seed,
                "period_s": self.period_s, "success": self.success,
                "handle_start": (None if self.handle_start is None
                                 else [float(v) for v in self.handle_start]),
                "stages": [{"subtask": s.subtask, "entity": s.entity, "gripper": s.gripper,
                            "reached": s.reached, "grid_min": s.grid.bounds_min.tolist(),
                            "grid_max": s.grid.bounds_max.tolist(),
                            "grid_shape": list(s.grid.shape)} for s in self.stages]}
        arrays: dict[str, Any] = {
            "meta": np.array(json.dumps(meta)), "waypoints": self.waypoints, "quats": self.quats, "gripper": self.gripper,
            "stage_of": self.stage_of}
        for k, s in enumerate(self.stages):
            arrays[f"cost_{k}"] = s.cost
            arrays[f"target_distance_{k}"] = s.target_distance
        tmp = path.with_suffix(".tmp.npz")
        np.savez_compressed(tmp, **arrays)
        tmp.replace(path)
        return path

    @classmethod
    def load(cls, path: Path) -> ZeroShotTrajectory:
        """Read a file written by :meth:`save`."""
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            stages = tuple(
                Stage(subtask=s["subtask"], entity=s["entity"],
                      grid=VoxelGrid(s["grid_min"], s["grid_max"], tuple(s["grid_shape"])),
                      cost=data[f"cost_{k}"], target_distance=data[f"target_distance_{k}"],
                      gripper=float(s["gripper"]), reached=bool(s["reached"]))
                for k, s in enumerate(meta["stages"]))
            return cls(task=meta["task"], source=meta["source"], seed=int(meta["seed"]),
                       waypoints=data["waypoints"], quats=data["quats"],
                       gripper=data["gripper"], stage_of=data["stage_of"].astype(np.int64),
                       period_s=float(meta["period_s"]), success=bool(meta["success"]),
                       stages=stages,
                       handle_start=(None if meta.get("handle_start") is None
                                     else np.array(meta["handle_start"], dtype=np.float64)))


def load_trajectories(folder: Path, task: str) -> list[ZeroShotTrajectory]:
    """Every trajectory of ``task`` in ``folder`` (sorted by file name).

    Raises:
        ConfigError: none there (``--prior on`` needs at least one).
    """
    found = [ZeroShotTrajectory.load(p) for p in sorted(folder.glob("*.npz"))
             if not p.name.endswith(".tmp.npz")]
    found = [t for t in found if t.task == task]
    if not found:
        raise ConfigError(f"no zero-shot trajectory of task {task!r} in {folder}: record them "
                          "first (voxposer learn-dynamics --record-zero-shot K)")
    return found


__all__ = ["Stage", "ZeroShotTrajectory", "load_trajectories"]
