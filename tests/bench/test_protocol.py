"""The evaluation protocol: seed sets, instruction splits, the constraint-blind control's jobs,
and the wiring of unseen instructions into the methods (no simulation here)."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest

from voxposer.bench import BenchConfig, EpisodeJob, EpisodeRecord
from voxposer.bench.methods import get_method
from voxposer.bench.protocol import DEV_SEEDS, SEED_SETS, TEST_SEEDS, get_seed_set
from voxposer.bench.results import record_key
from voxposer.bench.tasks import TASKS
from voxposer.bench.tasks.move_to_region import MoveToRegion
from voxposer.errors import ConfigError


class _Constrained(MoveToRegion):
    """move_to_region declared as carrying a constraint (its blind control: the reference)."""

    name = "constrained"
    constraint: ClassVar[str | None] = "avoidance map"

    def blind(self, attrs):
        return self.reference(attrs)


def test_seed_sets_map_to_their_ranges_and_are_disjoint() -> None:
    assert (DEV_SEEDS.first, DEV_SEEDS.last) == (0, 9_999)
    assert TEST_SEEDS.first == 100_000 and TEST_SEEDS.last >= TEST_SEEDS.first
    assert set(SEED_SETS) == {"dev", "test"}
    dev, test = (set(range(s.first, s.last + 1)) for s in (DEV_SEEDS, TEST_SEEDS))
    assert not dev & test
    cfg = BenchConfig(tasks=("move_to_region",), splits=("seen",), seeds="test", episodes=20)
    assert list(cfg.seed_list()) == list(range(100_000, 100_020))
    assert [j.seed for j in cfg.jobs()] == list(range(100_000, 100_020))
    assert {j.seed_set for j in cfg.jobs()} == {"test"}
    assert BenchConfig(episodes=3).seed_set == "dev"
    assert list(BenchConfig(episodes=3).seed_list()) == [0, 1, 2]
    adhoc = BenchConfig(seed=7, episodes=2)
    assert adhoc.seed_set == "adhoc" and list(adhoc.seed_list()) == [7, 8]
    with pytest.raises(ConfigError, match="10000 seeds"):
        get_seed_set("dev").seeds(10_001)


def test_unknown_names_list_the_allowed_values() -> None:
    with pytest.raises(ConfigError, match=r"'nope'.*dev \(0–9999\), test \(100000–"):
        BenchConfig(seeds="nope")
    with pytest.raises(ConfigError, match=r"'sometimes'.*seen, unseen"):
        BenchConfig(instructions="sometimes", llm="default")
    with pytest.raises(ConfigError, match="reference-blind"):
        BenchConfig(llm="gpt-17")
    with pytest.raises(ConfigError, match="not both"):
        BenchConfig(seeds="dev", seed=3)


@pytest.mark.parametrize("llm", ["reference", "reference-blind"])
def test_unseen_instructions_are_refused_for_reference_programs(llm: str, monkeypatch) -> None:
    monkeypatch.setitem(TASKS, "constrained", _Constrained())
    with pytest.raises(ConfigError, match="has no prompts"):
        BenchConfig(tasks=("constrained",), llm=llm, instructions="unseen")


def test_instruction_split_is_part_of_the_identity() -> None:
    seen = EpisodeJob("push_to_pos", "seen", 3, llm="default")
    unseen = EpisodeJob("push_to_pos", "seen", 3, llm="default", instructions="unseen")
    assert seen.key != unseen.key
    for job in (seen, unseen):
        assert record_key(EpisodeRecord.for_job(job).to_json()) == job.key
    old = EpisodeRecord.for_job(seen).to_json()
    del old["instructions"]  # a record written before the field existed: seen instructions
    assert record_key(old) == seen.key
    cfg = BenchConfig(tasks=("push_to_pos",), splits=("seen",), episodes=1, llm="default",
                      instructions="unseen")
    assert [j.instructions for j in cfg.jobs()] == ["unseen"]


def test_reference_blind_skips_tasks_without_a_constraint(monkeypatch) -> None:
    monkeypatch.setitem(TASKS, "constrained", _Constrained())
    cfg = BenchConfig(tasks=("move_to_region", "constrained"), splits=("seen",), episodes=2,
                      llm="reference-blind")
    assert cfg.skipped_tasks == ("move_to_region",)
    assert {j.task for j in cfg.jobs()} == {"constrained"} and len(cfg.jobs()) == 2
    assert BenchConfig(tasks=("move_to_region",), llm="reference").skipped_tasks == ()
    with pytest.raises(ConfigError, match="carries a constraint"):
        BenchConfig(tasks=("move_to_region",), llm="reference-blind")
    with pytest.raises(ConfigError, match="voxposer"):
        BenchConfig(tasks=("constrained",), llm="reference-blind", method="llm_primitives")


def test_reference_blind_episode_replays_the_blind_programs(world, monkeypatch) -> None:
    from voxposer.bench import run_episode

    calls: list[dict[str, str]] = []

    class _Tracking(_Constrained):
        def blind(self, attrs):
            calls.append(dict(attrs))
            return super().blind(attrs)

    monkeypatch.setitem(TASKS, "constrained", _Tracking())
    rec = run_episode(EpisodeJob("constrained", "seen", 0, llm="reference-blind",
                                 max_time_s=20.0), world)
    assert rec.error is None, rec.error
    assert len(calls) == 1 and rec.llm == "reference-blind" and rec.llm_calls > 0
    assert rec.success  # this "blind" control is the full reference: it must still succeed


class _Capture:
    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.args = args
        _Capture.last = self

    def run(self, instruction: str) -> None:
        pass

    last: ClassVar[Any] = None


@pytest.mark.parametrize("instructions, held_out", [("seen", None), ("unseen", "push_to_pos")])
def test_unseen_instructions_hold_the_task_out_of_the_prompts(monkeypatch, instructions: str,
                                                              held_out: str | None) -> None:
    import voxposer.bench.primitives as primitives
    import voxposer.pipeline as pipeline

    def fake_runtime(*args: Any, **kwargs: Any) -> tuple[_Capture, None]:
        return _Capture(kwargs["lmp_config"]), None

    monkeypatch.setattr(pipeline, "voxposer_runtime", fake_runtime)
    monkeypatch.setattr(pipeline.Embodiment, "simulated",
                        classmethod(lambda cls, world, perception=None: None))
    monkeypatch.setattr(primitives, "PrimitivesRuntime",
                        lambda body, backend, config, **kw: _Capture(config))
    world = SimpleNamespace(config=SimpleNamespace(controller=SimpleNamespace(max_speed_scale=5)))
    setup = SimpleNamespace(task="push_to_pos", instruction="push it", rng=np.random.default_rng())
    for method in ("voxposer", "llm_primitives"):
        get_method(method).run(world, None, setup, 10.0, instructions)  # type: ignore[arg-type]
        config = _Capture.last.args[0]
        assert (None if config is None else config.held_out_task) == held_out


def test_the_baseline_loads_its_prompt_without_the_held_out_task(monkeypatch) -> None:
    from voxposer.bench.primitives import PRIMITIVES_SPEC, PrimitivesRuntime
    from voxposer.lmp.prompt import load_prompt
    from voxposer.lmp.registry import LMPConfig

    full = load_prompt(PRIMITIVES_SPEC.name)
    assert full.tasks, "the llm_primitives prompt demonstrates no task: nothing to hold out"
    task = sorted(full.tasks)[0]
    rt = object.__new__(PrimitivesRuntime)
    rt._prompts, rt.config = {}, LMPConfig(held_out_task=task)
    folded = rt.prompt(PRIMITIVES_SPEC.name)
    assert task not in folded.tasks and len(folded.examples) < len(full.examples)


def test_unseen_instructions_check_every_fold_before_running(monkeypatch) -> None:
    """A fold that would leave some LMP without an example stops the run at configuration."""
    import voxposer.lmp.prompt as prompt_module
    from voxposer.bench.runner import BenchConfig

    checked: list[str] = []

    def fake_check(task: str, prompt_dir=None):
        checked.append(task)
        if task == "push_to_pos":
            raise ConfigError("the fold holding out task 'push_to_pos' leaves the prompt of "
                              "LMP(s) composer with no few-shot example")
        return {}

    monkeypatch.setattr(prompt_module, "check_fold", fake_check)
    with pytest.raises(ConfigError, match="composer"):
        BenchConfig(tasks=("move_to_region", "push_to_pos"), llm="default",
                    instructions="unseen", seeds="dev", episodes=1)
    assert checked == ["move_to_region", "push_to_pos"]
    checked.clear()
    BenchConfig(tasks=("move_to_region",), llm="default", instructions="unseen", seeds="dev",
                episodes=1)
    assert checked == ["move_to_region"]
