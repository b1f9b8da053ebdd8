"""Tasks register themselves: a new task is one module, with no list to edit."""

from __future__ import annotations

import pytest

from voxposer.bench.task import BenchTask, registered_tasks
from voxposer.bench.tasks import TASKS
from voxposer.bench.tasks.push_to_pos import PushToPos
from voxposer.errors import ConfigError


def test_every_task_module_registered_its_task_in_table_4_order() -> None:
    defined = {n for n, cls in registered_tasks().items()
               if cls.__module__.startswith("voxposer.bench.tasks.")}
    assert defined == set(TASKS) and len(TASKS) == 13
    order = list(TASKS)
    assert order[0] == "move_to_preposition" and order[-1] == "push_to_pos"


def test_a_subclass_registers_on_definition_and_names_are_unique() -> None:
    class PushFurther(PushToPos):
        name = "push_further_test_only"

    assert registered_tasks()["push_further_test_only"] is PushFurther

    class Partial(BenchTask):  # abstract: not a task
        name = "partial_test_only"

    assert "partial_test_only" not in registered_tasks()
    with pytest.raises(ConfigError, match="push_to_pos"):
        type("Impostor", (PushToPos,), {"name": "push_to_pos"})
