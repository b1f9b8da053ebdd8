"""The LLM + Primitives baseline's reference programs (``BenchTask.primitives_reference``).

Every task answers its instruction with one ``llm_primitives`` program that the sandbox accepts
and that uses only the baseline's API (the prompt's functions, ``np``, a few builtins); on a
dev seed, replaying it (``--method llm_primitives --llm reference``) succeeds for a few
representative tasks.
"""

from __future__ import annotations

import ast

import pytest

from voxposer.bench import TASKS, run_episode
from voxposer.bench.attributes import check_split
from voxposer.bench.episode import EpisodeJob
from voxposer.bench.methods import get_method
from voxposer.bench.primitives_programs import API, LMP
from voxposer.bench.task import episode_rng
from voxposer.lmp.sandbox_compile import compile_sandboxed

#: builtins a program may call besides the API (the sandbox provides them).
BUILTINS = frozenset({"range", "min", "max", "abs", "len"})
#: one representative of each kind of program: a push, a detour, a velocity zone, a drawer.
BEHAVIOURAL = ("push_to_pos", "move_to_pos_min_distance", "move_to_pos_velocity_in_region",
               "close_drawer")


def _attributes(name: str, split: str, seed: int) -> dict[str, str]:
    task = TASKS[name]
    return task.sample_attributes(episode_rng(name, split, seed), check_split(split))


def _free_names(code: str) -> set[str]:
    """Names the code reads without having assigned them (what it needs from outside)."""
    tree = ast.parse(code)
    stored = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)
              and isinstance(n.ctx, ast.Store)}
    stored |= {a.arg for n in ast.walk(tree) if isinstance(n, ast.Lambda) for a in n.args.args}
    loaded = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)
              and isinstance(n.ctx, ast.Load)}
    return loaded - stored


@pytest.mark.parametrize("name", list(TASKS))
@pytest.mark.parametrize("split", ["seen", "unseen"])
def test_every_task_answers_its_instruction_with_one_api_program(name: str, split: str) -> None:
    task = TASKS[name]
    for seed in range(3):
        attrs = _attributes(name, split, seed)
        progs = task.primitives_reference(attrs)
        assert progs is not None, f"{name} has no primitives reference"
        entries = progs.entries()
        assert [(e["lmp"], e["query"]) for e in entries] == [(LMP, task.instruction(attrs))]
        code = entries[0]["responses"][0]
        compile_sandboxed(code)  # parses, and uses no construct the sandbox refuses
        assert _free_names(code) <= API | BUILTINS, (attrs, _free_names(code) - API - BUILTINS)
        called = {n.func.id for n in ast.walk(ast.parse(code))
                  if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}
        assert called <= API | BUILTINS
        assert "move_to_pos" in called, "the program moves the robot"


def test_the_method_replays_them_keyed_by_the_instruction() -> None:
    attrs = _attributes("push_to_pos", "seen", 0)
    backend = get_method("llm_primitives").reference_backend(TASKS["push_to_pos"], attrs)
    assert backend.model == "reference-programs"


def test_place_constants_are_the_places_target_points() -> None:
    progs = TASKS["move_to_region"].primitives_reference({"region": "right side of the table"})
    assert progs is not None
    code = progs.code(LMP, "move to the right side of the table")
    assert "np.array([-0.200, 0.280, 0.050])" in code


@pytest.mark.parametrize("name", BEHAVIOURAL)
def test_the_reference_program_succeeds_on_a_dev_seed(world, name: str) -> None:
    rec = run_episode(EpisodeJob(name, "seen", 0, method="llm_primitives", llm="reference",
                                 seed_set="dev"), world)
    assert rec.error is None, rec.error
    assert rec.success, (rec.instruction, rec.reason, rec.program_error)
    assert rec.program_error is None, rec.program_error
    assert [p["lmp"] for p in rec.programs] == [LMP]
