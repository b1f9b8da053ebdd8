"""The multi-step instruction suite (``voxposer bench --suite multistep``).

2–3 step instructions built from the 13 tasks' pieces ("hover 10cm over the [obj], then move to
the [region]", "push the [obj] to the [pos] and then move away from it"), each step with its own
check over the episode's trace and a check that the steps were done in the order asked
(:mod:`~voxposer.bench.multistep.order`). Entries are :class:`MultiStepTask` declarations in
:mod:`~voxposer.bench.multistep.suite`; they live in :data:`ENTRIES`, never in the 13-task
registry. ``get_entry(name)`` returns one; unknown names raise ConfigError listing the entries.
"""

from __future__ import annotations

from typing import Final

from voxposer.bench.multistep import suite as _suite  # noqa: F401 - declares the entries
from voxposer.bench.multistep.step import Step
from voxposer.bench.multistep.task import MultiStepTask, suite_entries
from voxposer.bench.tasks import TASKS
from voxposer.errors import ConfigError

#: entry name → entry, in declaration order.
ENTRIES: Final[dict[str, MultiStepTask]] = {n: cls() for n, cls in suite_entries().items()}

_CLASH = sorted(set(ENTRIES) & set(TASKS))
if _CLASH:  # records are keyed by task name: the two registries must not share one
    raise ConfigError(f"multi-step entries {', '.join(_CLASH)} share a name with a task")


def get_entry(name: str) -> MultiStepTask:
    """The suite entry called ``name``; raises ConfigError listing the entries."""
    if name not in ENTRIES:
        raise ConfigError(f"unknown multi-step entry {name!r}; entries are: "
                          f"{', '.join(ENTRIES)}")
    return ENTRIES[name]


__all__ = ["ENTRIES", "MultiStepTask", "Step", "get_entry"]
