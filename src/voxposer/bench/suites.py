"""The benchmark's instruction suites: ``tasks`` (the paper's 13 tasks) and ``multistep``.

``--suite`` picks one; its names are what ``--tasks`` selects from. :func:`suite_task` looks a
name up in a suite (ConfigError listing the suite's names), :func:`suite_names` lists them.
Records carry their suite (``EpisodeRecord.suite``).
"""

from __future__ import annotations

from typing import Final

from voxposer.bench.task import BenchTask
from voxposer.errors import ConfigError

#: the paper's 13 single-instruction tasks (the default suite).
TASKS_SUITE: Final = "tasks"
#: the multi-step instructions (:mod:`voxposer.bench.multistep`).
MULTISTEP_SUITE: Final = "multistep"
SUITES: Final[tuple[str, ...]] = (TASKS_SUITE, MULTISTEP_SUITE)


def check_suite(suite: str) -> str:
    """``suite`` if it is a suite; raises ConfigError listing them otherwise."""
    if suite not in SUITES:
        raise ConfigError(f"unknown suite {suite!r}; suites are: {', '.join(SUITES)}")
    return suite


def suite_names(suite: str) -> tuple[str, ...]:
    """Every task (or entry) name of ``suite``, in its order."""
    if check_suite(suite) == MULTISTEP_SUITE:
        from voxposer.bench.multistep import ENTRIES

        return tuple(ENTRIES)
    from voxposer.bench.tasks import TASKS

    return tuple(TASKS)


def suite_task(suite: str, name: str) -> BenchTask:
    """The task (or entry) ``name`` of ``suite``; raises ConfigError listing the suite's names."""
    if check_suite(suite) == MULTISTEP_SUITE:
        from voxposer.bench.multistep import get_entry

        return get_entry(name)
    from voxposer.bench.tasks import get_task

    return get_task(name)
