"""The benchmark's Gymnasium ids, registered without importing the simulator: each id's entry
point (:class:`voxposer.bench.gym_tasks.TaskEnv`) loads only when ``gym.make`` builds it."""

from __future__ import annotations

from typing import Final

from voxposer.bench.tasks import TASKS, get_task

#: Gymnasium namespace of the benchmark's environments.
NAMESPACE: Final = "voxposer"


def env_id(task: str) -> str:
    """The registered id of a task ("push_to_pos" → "voxposer/PushToPos-v0")."""
    return f"{NAMESPACE}/{type(get_task(task)).__name__}-v0"


def register_task_envs() -> tuple[str, ...]:
    """Register every task under :data:`NAMESPACE` (once; later calls change nothing)."""
    import gymnasium as gym

    ids = []
    for name in TASKS:
        ident = env_id(name)
        if ident not in gym.registry:
            gym.register(id=ident, entry_point="voxposer.bench.gym_tasks:TaskEnv",
                         kwargs={"task": name})
        ids.append(ident)
    return tuple(ids)


__all__ = ["NAMESPACE", "env_id", "register_task_envs"]
