"""The sqlite response cache: hits, misses, persistence, concurrency."""

from __future__ import annotations

import threading
from dataclasses import replace
from pathlib import Path

import pytest

from voxposer.errors import LLMError
from voxposer.lmp.backends import (
    CachedBackend,
    ChatMessage,
    LLMBackend,
    LLMRequest,
    LLMResponse,
    ResponseCache,
)


class CountingBackend(LLMBackend):
    """Answers with a counter, so a repeated answer proves a cache hit."""

    name = "counting"

    def __init__(self, model: str = "m1", fail: bool = False) -> None:
        self._model = model
        self.calls = 0
        self.fail = fail
        self._lock = threading.Lock()

    @property
    def model(self) -> str:
        return self._model

    def complete(self, request: LLMRequest) -> LLMResponse:
        with self._lock:
            self.calls += 1
            n = self.calls
        if self.fail:
            raise LLMError("down")
        return LLMResponse(text=f"answer {n}", model=self._model, prompt_tokens=4, seconds=1.5)


def req(query: str = "q", **kw: object) -> LLMRequest:
    return LLMRequest(messages=(ChatMessage("user", query),), **kw)  # type: ignore[arg-type]


def test_miss_then_hit_marks_cached(tmp_path: Path) -> None:
    inner = CountingBackend()
    llm = CachedBackend(inner, ResponseCache(tmp_path / "c.sqlite"))
    first = llm.complete(req())
    second = llm.complete(req())
    assert (first.text, first.cached) == ("answer 1", False)
    assert (second.text, second.cached) == ("answer 1", True)
    assert second.prompt_tokens == 4 and second.extra["original_seconds"] == 1.5
    assert inner.calls == 1
    assert llm.name == "counting" and llm.model == "m1"


@pytest.mark.parametrize(
    "other",
    [req("other query"), req(temperature=0.7), req(max_tokens=9), req(stop=("#",)),
     req(prefix_id="composer")],
)  # fmt: skip
def test_any_request_difference_is_a_miss(tmp_path: Path, other: LLMRequest) -> None:
    inner = CountingBackend()
    llm = CachedBackend(inner, ResponseCache(tmp_path / "c.sqlite"))
    llm.complete(req())
    assert llm.complete(other).text == "answer 2"


def test_requests_together_ask_only_the_misses_and_keep_the_order(tmp_path: Path) -> None:
    inner = CountingBackend()
    llm = CachedBackend(inner, ResponseCache(tmp_path / "c.sqlite"))
    llm.complete(req("b"))  # answer 1
    together = llm.complete_many([req("a"), req("b"), req("c")])
    assert [r.text for r in together] == ["answer 2", "answer 1", "answer 3"]
    assert [r.cached for r in together] == [False, True, False] and inner.calls == 3
    again = llm.complete_many([req("c"), req("a")])  # both stored now
    assert [r.text for r in again] == ["answer 3", "answer 2"] and inner.calls == 3


def test_the_context_hint_is_not_part_of_the_key(tmp_path: Path) -> None:
    inner = CountingBackend()
    llm = CachedBackend(inner, ResponseCache(tmp_path / "c.sqlite"))
    llm.complete(req())
    hinted = replace(req(), context_messages=1)
    assert hinted.key("b", "m") == req().key("b", "m")
    assert llm.complete(hinted).cached and inner.calls == 1


def test_model_is_part_of_the_key(tmp_path: Path) -> None:
    cache = ResponseCache(tmp_path / "c.sqlite")
    CachedBackend(CountingBackend("m1"), cache).complete(req())
    assert CachedBackend(CountingBackend("m2"), cache).complete(req()).cached is False


def test_persists_across_instances(tmp_path: Path) -> None:
    path = tmp_path / "sub" / "c.sqlite"
    first = CachedBackend(CountingBackend(), ResponseCache(path))
    first.complete(req())
    first.close()
    inner = CountingBackend()
    again = CachedBackend(inner, ResponseCache(path)).complete(req())
    assert again.cached and again.text == "answer 1" and inner.calls == 0


def test_failures_are_not_cached(tmp_path: Path) -> None:
    cache = ResponseCache(tmp_path / "c.sqlite")
    with pytest.raises(LLMError):
        CachedBackend(CountingBackend(fail=True), cache).complete(req())
    assert len(cache) == 0


def test_threads_share_one_cache(tmp_path: Path) -> None:
    inner = CountingBackend()
    llm = CachedBackend(inner, ResponseCache(tmp_path / "c.sqlite"))
    errors: list[BaseException] = []

    def work(i: int) -> None:
        try:
            for j in range(20):
                llm.complete(req(f"q{(i * 20 + j) % 10}"))
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    assert len(llm.cache) == 10
    assert 10 <= inner.calls <= 40  # racing misses may both compute; never more than one per thread


def test_clear(tmp_path: Path) -> None:
    cache = ResponseCache(tmp_path / "c.sqlite")
    llm = CachedBackend(CountingBackend(), cache)
    llm.complete(req())
    cache.clear()
    assert len(cache) == 0 and llm.complete(req()).cached is False


def test_opening_a_new_cache_retries_when_another_process_is_turning_it_to_wal(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Two benchmark workers opening a fresh cache at once: sqlite tells one "locked" at once
    (no busy wait, a deadlock otherwise); the cache must retry, not fail the worker."""
    import sqlite3

    import voxposer.lmp.backends.cache as module

    real_connect = sqlite3.connect
    refusals = []

    class Contended:
        def __init__(self, conn: sqlite3.Connection) -> None:
            self.conn = conn

        def execute(self, sql: str, *args: object) -> sqlite3.Cursor:
            if sql.startswith("PRAGMA journal_mode") and len(refusals) < 2:
                refusals.append(sql)
                raise sqlite3.OperationalError("database is locked")
            return self.conn.execute(sql, *args)

        def __getattr__(self, name: str) -> object:
            return getattr(self.conn, name)

    monkeypatch.setattr(module.sqlite3, "connect",
                        lambda *a, **k: Contended(real_connect(*a, **k)))
    cache = module.ResponseCache(tmp_path / "fresh" / "cache.sqlite")
    assert len(refusals) == 2
    assert cache.get("nothing yet") is None
