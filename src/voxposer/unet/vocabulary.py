"""Word tokens of instructions and the vocabulary built from the training instructions.

Tokens are lower-case runs of letters and digits ("move to the left of the pink block" → 8
tokens). Id 0 pads, id 1 is the unknown token (every word not in the training instructions).
No torch here: the data generator records the vocabulary in its manifest.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer.errors import ConfigError

PAD: Final = "<pad>"
UNK: Final = "<unk>"
PAD_ID: Final = 0
UNK_ID: Final = 1
_WORD = re.compile(r"[a-z0-9]+")


def tokenise(instruction: str) -> list[str]:
    """The word tokens of ``instruction``, lower-cased, punctuation dropped."""
    return _WORD.findall(instruction.lower())


@dataclass(frozen=True)
class Vocabulary:
    """Word → id; ``words[0]`` is :data:`PAD`, ``words[1]`` is :data:`UNK`.

    Attributes:
        words: every token, in id order.
    """

    words: tuple[str, ...]

    def __post_init__(self) -> None:
        if self.words[:2] != (PAD, UNK):
            raise ConfigError(f"a vocabulary starts with {PAD!r}, {UNK!r}; got "
                              f"{list(self.words[:2])!r}")
        if len(set(self.words)) != len(self.words):
            raise ConfigError("a vocabulary lists each word once")
        object.__setattr__(self, "_ids", {w: i for i, w in enumerate(self.words)})

    @classmethod
    def build(cls, instructions: Iterable[str]) -> Vocabulary:
        """The sorted words of ``instructions`` after :data:`PAD` and :data:`UNK`."""
        words = sorted({t for text in instructions for t in tokenise(text)})
        return cls((PAD, UNK, *words))

    def __len__(self) -> int:
        return len(self.words)

    def ids(self, instruction: str) -> list[int]:
        """Token ids of ``instruction`` (:data:`UNK_ID` for unknown words; at least one id)."""
        table: dict[str, int] = self.__dict__["_ids"]
        return [table.get(t, UNK_ID) for t in tokenise(instruction)] or [UNK_ID]

    def batch(self, instructions: Sequence[str]) -> NDArray[np.int64]:
        """Padded token ids, shape (B, L_max), :data:`PAD_ID` after each instruction's end."""
        rows = [self.ids(text) for text in instructions]
        out = np.full((len(rows), max(map(len, rows), default=1)), PAD_ID, dtype=np.int64)
        for i, row in enumerate(rows):
            out[i, :len(row)] = row
        return out


__all__ = ["PAD", "PAD_ID", "UNK", "UNK_ID", "Vocabulary", "tokenise"]
