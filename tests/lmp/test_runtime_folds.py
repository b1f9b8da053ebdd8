"""The LMP runtime in an "unseen instruction" fold: what it sends, under which prefix id."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.lmp import LMPConfig, LMPRuntime, RecordingHandler, make_tabletop_scene
from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.prefix_state import PrefixState, PrefixStateStore, prefix_key
from voxposer.lmp.backends.replay import RecordingBackend, ReplayBackend
from voxposer.lmp.prompt import load_prompt

RECORDINGS = Path(__file__).parent / "recordings"
INSTRUCTION = "move to the left of the blue block while staying away from the green block"
TASK = "move_to_preposition"  # tags examples of planner, composer and get_affordance_map


class Spy(LLMBackend):
    """Keeps every request it forwards (a test double)."""

    name = "spy"

    def __init__(self, inner: LLMBackend) -> None:
        self.inner = inner
        self.requests: list[LLMRequest] = []

    @property
    def model(self) -> str:
        return self.inner.model

    def complete(self, request: LLMRequest) -> LLMResponse:
        self.requests.append(request)
        return self.inner.complete(request)


def run(held_out: str | None, record: Path | None = None) -> list[LLMRequest]:
    replay: LLMBackend = ReplayBackend(RECORDINGS / "closed_loop.jsonl")
    spy = Spy(RecordingBackend(replay, record) if record else replay)
    rt = LMPRuntime(make_tabletop_scene(), spy, handler=RecordingHandler(),
                    # every LMP asks the model (no exact-name shortcut), so each fold is seen
                    config=LMPConfig(held_out_task=held_out, resolve_exact_names=False))
    rt.run(INSTRUCTION)
    assert len(rt.handler.requests) == 1  # type: ignore[attr-defined]
    return spy.requests


def lmp(request: LLMRequest) -> str:
    return (request.prefix_id or "").split("~")[0]


def test_fold_requests_lack_the_held_out_examples_and_use_their_own_prefix_id(
        tmp_path: Path) -> None:
    default = {lmp(r): r for r in run(None)}
    fold = {lmp(r): r for r in run(TASK, tmp_path / "rec.jsonl")}
    assert set(fold) == set(default) >= {"planner", "composer", "get_affordance_map",
                                         "get_avoidance_map", "parse_query_obj"}
    changed = set()
    for name, request in fold.items():
        prompt = load_prompt(name)
        sent = {m.content for m in request.messages[:-1]}
        for example in prompt.examples:
            assert (example.user in sent) == (TASK not in example.tasks), (name, example.user)
        assert request.messages[-1] == default[name].messages[-1]  # the same query
        if any(TASK in e.tasks for e in prompt.examples):
            changed.add(name)
            assert request.prefix_id == f"{name}~{TASK}" != default[name].prefix_id
            assert len(request.messages) < len(default[name].messages)
        else:  # the fold left this prompt alone: the very request of the default run
            assert request == default[name] and request.prefix_id == name
    assert changed == {"planner", "composer", "get_affordance_map"}
    assert all(r.prefix_id == lmp(r) for r in default.values())
    recorded = [json.loads(line) for line in (tmp_path / "rec.jsonl").read_text().splitlines()]
    assert {e["lmp"] for e in recorded} == set(fold)  # recordings name the LMP, not the fold


def test_default_requests_are_the_full_prompts() -> None:
    for request in run(None):
        prompt = load_prompt(lmp(request))
        n = prompt.n_prefix_messages  # then the bank examples chosen for the query (if any)
        assert request.messages[:n] == prompt.messages("")[:n]


def test_runtime_rejects_a_fold_that_empties_a_prompt_before_running(tmp_path: Path) -> None:
    d = tmp_path / "prompts"
    d.mkdir()
    for name in ("planner", "composer", "parse_query_obj", "get_affordance_map",
                 "get_avoidance_map", "get_rotation_map", "get_velocity_map", "get_gripper_map"):
        tag = "push_to_pos" if name == "get_velocity_map" else "none"
        (d / f"{name}.txt").write_text(f"### system\ns\n### user [tasks: {tag}]\n# Query: q\n"
                                       "### assistant\nx = 1\n", encoding="utf-8")
    backend = Spy(ReplayBackend([]))
    with pytest.raises(ConfigError, match="'push_to_pos' leaves the prompt of LMP "
                                          "'get_velocity_map'"):
        LMPRuntime(make_tabletop_scene(), backend,
                   config=LMPConfig(prompt_dir=str(d), held_out_task="push_to_pos"))
    assert backend.requests == []
    LMPRuntime(make_tabletop_scene(), backend,
               config=LMPConfig(prompt_dir=str(d), held_out_task="drop_to_pos"))


def test_a_fold_prefix_is_stored_beside_the_default_one(tmp_path: Path) -> None:
    """The disk key hashes the prefix text, so a fold's prefix never overwrites the default's."""
    store = PrefixStateStore(tmp_path)
    keys = {}
    for held_out, n in ((None, 3), (TASK, 2)):
        prompt = load_prompt("composer", held_out_task=held_out)
        text = "\n".join(m.content for m in prompt.messages("")[:-1])
        keys[held_out] = prefix_key("model-fp", "runtime-1", 4096, text)
        store.save(PrefixState(keys[held_out], np.arange(n, dtype=np.int32), b"x" * n),
                   prompt.prefix_id)
    assert keys[None] != keys[TASK]
    assert sorted(p.name.split("-")[0] for p in tmp_path.glob("*.kv")) == \
        ["composer", f"composer_{TASK}"]
    default, fold = store.load(keys[None]), store.load(keys[TASK])
    assert default is not None and default.n_tokens == 3
    assert fold is not None and fold.n_tokens == 2
