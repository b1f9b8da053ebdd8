"""Prefix states on disk: round trip, keys, corruption, pruning."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from voxposer.lmp.backends.prefix_state import (
    PrefixState,
    PrefixStateStore,
    file_fingerprint,
    prefix_key,
)


def state(key: str, n: int = 5, size: int = 1000) -> PrefixState:
    return PrefixState(key=key, tokens=np.arange(n, dtype=np.int32), data=os.urandom(size))


def test_round_trip(tmp_path: Path) -> None:
    store = PrefixStateStore(tmp_path / "s")
    original = state(prefix_key("sha", "rt", 4096, "header"))
    path = store.save(original, prefix_id="planner/v1")
    assert path.name.startswith("planner_v1-")
    loaded = store.load(original.key)
    assert loaded is not None
    assert loaded.data == original.data and np.array_equal(loaded.tokens, original.tokens)
    assert loaded.n_tokens == 5


def test_key_depends_on_model_runtime_context_and_text() -> None:
    base = prefix_key("sha", "rt", 4096, "header")
    assert base == prefix_key("sha", "rt", 4096, "header")
    others = {
        prefix_key("sha2", "rt", 4096, "header"),
        prefix_key("sha", "rt2", 4096, "header"),
        prefix_key("sha", "rt", 8192, "header"),
        prefix_key("sha", "rt", 4096, "header "),
    }
    assert base not in others and len(others) == 4


def test_missing_and_corrupt_files(tmp_path: Path) -> None:
    store = PrefixStateStore(tmp_path / "s")
    assert store.load("0" * 64) is None
    good = state("a" * 64)
    path = store.save(good)
    path.write_bytes(path.read_bytes()[:-10])  # truncated
    assert store.load(good.key) is None
    assert not path.exists()


def test_prune_keeps_the_most_recent(tmp_path: Path) -> None:
    store = PrefixStateStore(tmp_path / "s", max_bytes=2500)
    keys = [c * 64 for c in "abc"]
    for i, key in enumerate(keys):
        path = store.save(state(key))
        os.utime(path, (1000 + i, 1000 + i))
    store.prune()
    assert store.load(keys[0]) is None
    assert store.load(keys[2]) is not None


def test_fingerprint(tmp_path: Path) -> None:
    f = tmp_path / "m.gguf"
    f.write_bytes(b"a" * 3_000_000)
    fp = file_fingerprint(f)
    assert fp.startswith("fp-") and fp == file_fingerprint(f)
    f.write_bytes(b"a" * 2_999_999 + b"b")
    assert file_fingerprint(f) != fp
    assert file_fingerprint(f, known_sha256="abc") == "abc"
