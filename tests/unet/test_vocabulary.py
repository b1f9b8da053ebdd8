"""Instruction tokens: a vocabulary from the training instructions, unknown words → <unk>."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.errors import ConfigError
from voxposer.unet.vocabulary import PAD_ID, UNK, UNK_ID, Vocabulary, tokenise


def test_tokenise_lower_cases_and_drops_punctuation() -> None:
    assert tokenise("Move to the LEFT of the pink block, at 5cm!") == [
        "move", "to", "the", "left", "of", "the", "pink", "block", "at", "5cm"]


def test_unseen_words_map_to_the_unknown_token() -> None:
    vocab = Vocabulary.build(["push the blue block to the right side of the table"])
    ids = vocab.ids("push the purple block to the left side")
    words = [vocab.words[i] for i in ids]
    assert words == ["push", "the", UNK, "block", "to", "the", UNK, "side"]
    assert ids[2] == ids[6] == UNK_ID
    assert vocab.ids("???") == [UNK_ID]  # no token at all: one unknown, never empty


def test_batch_pads_after_each_instruction() -> None:
    vocab = Vocabulary.build(["a b c", "d"])
    batch = vocab.batch(["a b c", "d"])
    assert batch.shape == (2, 3)
    np.testing.assert_array_equal(batch[1, 1:], [PAD_ID, PAD_ID])
    assert batch[1, 0] == vocab.words.index("d")


def test_a_vocabulary_must_start_with_pad_and_unk() -> None:
    with pytest.raises(ConfigError, match="starts with"):
        Vocabulary(("a", "b"))
