"""Replay/record backends, prompt files, code extraction."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from voxposer.errors import LLMError
from voxposer.lmp import LMP_SPECS
from voxposer.lmp.backends.base import ChatMessage, LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.backends.replay import RecordingBackend, ReplayBackend
from voxposer.lmp.codetext import extract_code
from voxposer.lmp.prompt import load_prompt

UNSEEN = ["right of", "back side of", "red", "orange", "purple", "cyan", "gray", "grey", "4cm",
          "6cm", "8cm", "10cm", "left side of the table", "front side of the table", "slower",
          "3x"]


class FakeModel(LLMBackend):
    name = "fake"

    def __init__(self) -> None:
        self.calls = 0

    @property
    def model(self) -> str:
        return "fake-1"

    def complete(self, request: LLMRequest) -> LLMResponse:
        self.calls += 1
        return LLMResponse(text=f"ret_val = {self.calls}", model=self.model)


def request(query: str) -> LLMRequest:
    return LLMRequest(messages=(ChatMessage("system", "s"), ChatMessage("user", f"# Query: {query}")),
                      prefix_id="parse_query_obj")


def test_record_then_replay_by_exact_key(tmp_path: Path) -> None:
    inner = FakeModel()
    recorder = RecordingBackend(inner, tmp_path / "rec.jsonl")
    first = recorder.complete(request("blue block")).text
    replay = ReplayBackend(tmp_path / "rec.jsonl")
    assert replay.model == "fake-1"
    out = replay.complete(request("blue block"))
    assert out.text == first and out.cached
    with pytest.raises(LLMError, match=r"parse_query_obj\('green block'\)"):
        replay.complete(request("green block"))


@pytest.mark.parametrize("name", list(LMP_SPECS))
def test_prompts_parse_and_hold_no_unseen_attributes(name: str) -> None:
    prompt = load_prompt(name)
    assert 5 <= len(prompt.examples) <= 20
    examples = "\n".join(e.user + "\n" + e.assistant for e in prompt.examples).lower()
    for word in UNSEEN:
        assert not re.search(rf"\b{re.escape(word)}\b", examples), (name, word)


@pytest.mark.parametrize("text, expected", [
    ("x = 1\n", "x = 1\n"),
    ("Sure! Here it is:\n```python\nx = 1\n```\nDone.", "x = 1\n"),
    ("```\ny = 2\n```", "y = 2\n"),
    ("The fix is below.\nx = f(1)\nret_val = x\nThis sets ret_val.", "x = f(1)\nret_val = x\n"),
])
def test_code_is_extracted_from_prose(text: str, expected: str) -> None:
    assert extract_code(text) == expected
