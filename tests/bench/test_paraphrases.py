"""The paraphrase split: twelve rewordings per task with the template's slots, dev and test
phrasings disjoint, test phrasings only on test seeds."""

from __future__ import annotations

import re

import pytest

from voxposer.bench.episode import EpisodeJob, run_episode
from voxposer.bench.paraphrases import PARAPHRASES, paraphrase, phrasings
from voxposer.bench.runner import BenchConfig
from voxposer.bench.tasks import TASKS
from voxposer.errors import ConfigError
from voxposer.lmp.backends.replay import ReplayBackend

_SLOT = re.compile(r"\[(\w+)\]")


@pytest.mark.parametrize("name", list(TASKS))
def test_every_task_has_twelve_phrasings_with_its_slots(name: str) -> None:
    task = TASKS[name]
    assert len(PARAPHRASES[name]) == 12 and len(set(PARAPHRASES[name])) == 12
    dev, test = phrasings(name, "dev"), phrasings(name, "test")
    assert len(dev) == len(test) == 6 and not set(dev) & set(test)
    for text in PARAPHRASES[name]:
        assert sorted(_SLOT.findall(text)) == sorted(task.slots), text
        assert text != task.template


def test_a_test_phrasing_never_reaches_a_dev_seed() -> None:
    attrs = {"obj": "blue block", "pos": "back side of the table"}
    dev = {paraphrase("push_to_pos", attrs, "dev", s) for s in range(24)}
    test = {paraphrase("push_to_pos", attrs, "test", s) for s in range(24)}
    assert len(dev) == len(test) == 6 and not dev & test
    assert all("blue block" in t and "back side of the table" in t for t in dev | test)
    with pytest.raises(ConfigError, match="dev, test"):
        phrasings("push_to_pos", "final")  # type: ignore[arg-type]


def test_reference_programs_cannot_answer_reworded_instructions() -> None:
    with pytest.raises(ConfigError, match="paraphrased"):
        BenchConfig(llm="reference", instructions="paraphrased")


def test_an_episode_carries_its_dev_phrasing(world) -> None:
    job = EpisodeJob("push_to_pos", "seen", 3, llm="replay", instructions="paraphrased",
                     seed_set="dev")
    rec = run_episode(job, world, backend=ReplayBackend([]))  # no recording: the LLM refuses
    assert rec.instruction == paraphrase("push_to_pos", rec.attributes, "dev", 3)
    assert rec.instruction not in {paraphrase("push_to_pos", rec.attributes, "test", s)
                                   for s in range(6)}
