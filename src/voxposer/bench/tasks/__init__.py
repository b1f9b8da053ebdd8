"""The benchmark's tasks: the paper's 13 simulated tasks (Table 4), in Table 4's row order.

Every module of this package that defines a :class:`~voxposer.bench.task.BenchTask` subclass
registers it on import; this package imports them all. Tasks of the paper come in the row order
of its Table 4, any others after them by name. ``get_task(name)`` returns a task; unknown names
raise ConfigError listing the known ones.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Final

from voxposer.bench.paper import TABLE4
from voxposer.bench.task import BenchTask, registered_tasks
from voxposer.errors import ConfigError

for _module in pkgutil.iter_modules(__path__):
    if not _module.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_module.name}")


def _order(task: BenchTask) -> tuple[int, str]:
    rows = list(TABLE4)
    return (rows.index(task.paper_row) if task.paper_row in rows else len(rows), task.name)


#: task name → task, in the row order of the paper's Table 4.
TASKS: Final[dict[str, BenchTask]] = {
    t.name: t for t in sorted((cls() for cls in registered_tasks().values()), key=_order)
}


def get_task(name: str) -> BenchTask:
    """The task called ``name``; raises ConfigError listing the known tasks."""
    if name not in TASKS:
        raise ConfigError(f"unknown task {name!r}; tasks are: {', '.join(TASKS)}")
    return TASKS[name]


__all__ = ["TASKS", "get_task"]
