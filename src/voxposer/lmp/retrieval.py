"""Few-shot examples chosen per query: the nearest examples of an LMP's example bank.

A small model copies the example nearest to its query, so a reworded instruction ("go to the
corner, keeping to the top of the block on the way") fares best when some example shows the same
wording. Each LMP's prompt keeps its fixed examples (their evaluated prefix is reused across
queries); an optional *bank* (``prompts/banks/<lmp>.txt``, the prompt file's marker format and
task tags, no system section) holds more, and the ``k`` bank examples whose queries are nearest
to the query are placed after the fixed ones, just before the query.

Nearness is BM25+ (``rank_bm25``; its document frequency term stays positive in a bank of a few
dozen examples, where Okapi's vanishes for a word half of them share) over the queries' words, with colours folded into
``<colour>`` and numbers into ``<n>``, so an example is chosen for how the query is phrased
(its verbs, clause order, connectives and the sides it names), not for the objects or
distances it names — which attribute values may appear in prompts is what the seen/unseen
attribute split governs, and the bank uses seen attributes only. An
"unseen instruction" fold leaves out the bank examples of its held-out task, as it does the fixed
ones (:meth:`ExampleBank.without_task`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Final

from rank_bm25 import BM25Plus

from voxposer.catalog import COLOR_NAMES
from voxposer.lmp.example import Example

QUERY_MARK: Final = "# Query:"
#: words every query shares; left out so they neither match nor dilute a match.
STOP_WORDS: Final = frozenset({"the", "a", "an", "of", "it", "its", "is"})
_TOKEN: Final = re.compile(r"[a-z]+|\d+(?:\.\d+)?")


def query_words(text: str) -> list[str]:
    """The tokens of ``text`` that nearness is computed on (lower case, values folded)."""
    out = []
    for token in _TOKEN.findall(text.lower()):
        if token in STOP_WORDS:
            continue
        if token[0].isdigit():
            token = "<n>"
        elif token in COLOR_NAMES:
            token = "<colour>"
        out.append(token)
    return out


def query_text(user: str) -> str:
    """The query of a user message: the text after its last ``# Query:`` line (all of it when
    there is none)."""
    lines = [ln for ln in user.splitlines() if ln.startswith(QUERY_MARK)]
    return lines[-1][len(QUERY_MARK):].strip() if lines else user.strip()


@dataclass(frozen=True)
class ExampleBank:
    """Examples to choose from by nearness to a query.

    Attributes:
        examples: the bank's examples, in file order (ties in nearness keep this order).
    """

    examples: tuple[Example, ...]
    _index: BM25Plus | None = field(default=None, init=False, repr=False, compare=False)
    _words: tuple[frozenset[str], ...] = field(default=(), init=False, repr=False,
                                               compare=False)

    def __post_init__(self) -> None:
        if self.examples:
            corpus = [query_words(query_text(e.user)) or ["<empty>"] for e in self.examples]
            object.__setattr__(self, "_index", BM25Plus(corpus))
            object.__setattr__(self, "_words", tuple(frozenset(c) for c in corpus))

    def without_task(self, task: str) -> ExampleBank:
        """This bank minus the examples tagged with ``task`` (an "unseen instruction" fold)."""
        kept = tuple(e for e in self.examples if task not in e.tasks)
        return self if len(kept) == len(self.examples) else ExampleBank(kept)

    def nearest(self, query: str, k: int) -> tuple[Example, ...]:
        """The (at most) ``k`` examples nearest to ``query``, the nearest last (so it stands
        next to the query); none that shares no word with it.

        Args:
            query: the query text (without the ``# Query:`` mark).
            k: how many to return (>= 0).
        """
        words = query_words(query)
        if k <= 0 or self._index is None or not words:
            return ()
        scores = self._index.get_scores(words)
        sharing = [i for i, w in enumerate(self._words) if w.intersection(words)]
        chosen = sorted(sharing, key=lambda i: (-scores[i], i))[:k]
        return tuple(self.examples[i] for i in reversed(chosen))

    @property
    def tasks(self) -> frozenset[str]:
        """Every task some bank example demonstrates."""
        return frozenset().union(*(e.tasks for e in self.examples))


__all__ = ["ExampleBank", "query_text", "query_words"]
