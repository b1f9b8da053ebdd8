"""The paper's 13-task simulated benchmark (Sec. 4.2, App. A.5, Table 4) and its baseline.

Public API:

* :data:`TASKS`, :func:`get_task` — the task registry; each :class:`BenchTask` declares its
  template, seen/unseen attributes, reset, success check and reference programs.
* :class:`Tolerances` — every success threshold, in one place; :data:`PLACES` — table regions.
* :func:`reset_episode`, :func:`run_episode`, :class:`EpisodeJob` — one episode.
* :class:`BenchConfig`, :func:`run_bench` — many episodes in parallel, appended to a JSONL;
  seed sets and instruction splits in :mod:`voxposer.bench.protocol`, code versions in
  :mod:`voxposer.bench.version`.
* :data:`METHODS` — "voxposer" and "llm_primitives" (the LLM + Primitives baseline, App. A.4).
* Gymnasium: importing this package registers every task as ``voxposer/<TaskClass>-v0``
  (:mod:`voxposer.bench.gym_ids`, :mod:`voxposer.bench.gym_tasks`), e.g. ``gym.make("voxposer/PushToPos-v0")``.
* The multi-step suite (:mod:`voxposer.bench.multistep`, ``voxposer bench --suite multistep``):
  2–3 step instructions with a check per step and for their order, kept out of :data:`TASKS`.
* CLI: ``voxposer bench`` (:mod:`voxposer.cli.bench`).
"""

from voxposer.bench.config import Tolerances
from voxposer.bench.episode import EpisodeJob, EpisodeRecord, run_episode
from voxposer.bench.gym_ids import register_task_envs
from voxposer.bench.methods import METHODS, get_method
from voxposer.bench.runner import BenchConfig, run_bench
from voxposer.bench.task import BenchTask, Verdict, reset_episode
from voxposer.bench.tasks import TASKS, get_task
from voxposer.places import PLACES, get_place

# Gymnasium's convention: an environment package registers its ids when imported.
register_task_envs()

__all__ = [
    "METHODS",
    "PLACES",
    "TASKS",
    "BenchConfig",
    "BenchTask",
    "EpisodeJob",
    "EpisodeRecord",
    "TaskEnv",
    "Tolerances",
    "Verdict",
    "get_method",
    "get_place",
    "get_task",
    "reset_episode",
    "run_bench",
    "run_episode",
]
