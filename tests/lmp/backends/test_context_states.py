"""Kept query contexts: the longest kept state that starts a request is found, the byte budget
evicts the least recently used, and a state larger than the budget is not kept."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.lmp.backends.context_states import ContextStates
from voxposer.lmp.backends.prefix_state import PrefixState


def state(tokens: list[int], nbytes: int = 100) -> PrefixState:
    return PrefixState(key="context", tokens=np.array(tokens, dtype=np.int32),
                       data=b"x" * (nbytes - 4 * len(tokens)))


def test_longest_kept_prefix_of_the_request_is_found() -> None:
    kept = ContextStates(10_000)
    short, long, other = state([1, 2, 3]), state([1, 2, 3, 4, 5]), state([1, 2, 9, 9])
    for s in (short, long, other):
        assert kept.add(s)
    assert kept.longest([1, 2, 3, 4, 5, 6]) is long
    assert kept.longest([1, 2, 3, 4, 7]) is short  # the long one diverges at its 5th token
    assert kept.longest([1, 2, 9, 9, 1]) is other
    assert kept.longest([7, 1, 2, 3]) is None
    assert kept.longest([1, 2, 3, 4, 5, 6], longer_than=5) is None  # nothing beats what is live
    assert kept.longest([1, 2]) is None  # every kept state is longer than the request


def test_budget_evicts_the_least_recently_used() -> None:
    kept = ContextStates(250)
    a, b, c = state([1, 1]), state([2, 2]), state([3, 3])
    kept.add(a)
    kept.add(b)
    assert kept.longest([1, 1, 5]) is a  # a is now the most recently used
    kept.add(c)  # 300 bytes > 250: b goes
    assert len(kept) == 2 and kept.nbytes == 200
    assert kept.longest([2, 2, 5]) is None
    assert kept.longest([1, 1, 5]) is a and kept.longest([3, 3, 5]) is c


def test_state_over_the_budget_is_not_kept_and_zero_keeps_nothing() -> None:
    kept = ContextStates(150)
    assert not kept.add(state([1, 2], nbytes=200))
    assert len(kept) == 0
    none = ContextStates(0)
    assert not none.add(state([1, 2]))
    assert none.longest([1, 2, 3]) is None
    with pytest.raises(ConfigError, match="-1 bytes must be >= 0"):
        ContextStates(-1)


def test_adding_the_same_tokens_again_replaces_the_state() -> None:
    kept = ContextStates(1_000)
    kept.add(state([4, 5], nbytes=100))
    newer = state([4, 5], nbytes=120)
    kept.add(newer)
    assert len(kept) == 1 and kept.nbytes == 120 and kept.longest([4, 5, 6]) is newer
