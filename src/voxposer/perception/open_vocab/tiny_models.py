"""Tiny random-weight OWLv2 and SAM models, saved like real ones, for tests and benchmarks.

They find random things (their weights are random) but have the real models' classes, inputs
and outputs, and load through the same from-a-directory path (:func:`save_tiny_models`), so the
whole pipeline runs without downloading anything. The detector's tokenizer is a CLIP tokenizer
over a vocabulary of letters, digits and a few words, with no merges.
"""

from __future__ import annotations

import json
import string
from pathlib import Path
from typing import Final

from voxposer.perception.open_vocab.weights import require

#: Whole words of the tiny tokenizer's vocabulary (everything else is spelled letter by letter).
_WORDS: Final = ("block", "drawer", "handle", "table", "robot", "gripper", "cabinet", "line")


def _save_tokenizer(directory: Path) -> int:
    """Write a tiny CLIP tokenizer (vocab.json, merges.txt) to ``directory`` and save it with
    ``save_pretrained``; its vocabulary size."""
    vocab = {"<|startoftext|>": 0, "<|endoftext|>": 1}
    for token in (*_WORDS, *string.ascii_lowercase, *string.digits):
        vocab.setdefault(token, len(vocab))
        vocab.setdefault(f"{token}</w>", len(vocab))
    (directory / "vocab.json").write_text(json.dumps(vocab))
    (directory / "merges.txt").write_text("#version: 0.2\n")
    tokenizer = require("transformers").CLIPTokenizer(str(directory / "vocab.json"),
                                                     str(directory / "merges.txt"))
    tokenizer.save_pretrained(str(directory))
    return len(vocab)


def save_tiny_detector(directory: str | Path, *, image_size: int = 64, seed: int = 0) -> Path:
    """Save a random ``Owlv2ForObjectDetection`` (hidden size 32, one layer, ``image_size``
    [px] input, 16 px patches) and its tokenizer to ``directory``; returns it."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    transformers, torch = require("transformers"), require("torch")
    torch.manual_seed(seed)
    vocab_size = _save_tokenizer(out)
    layer = {"hidden_size": 32, "intermediate_size": 64, "num_hidden_layers": 1,
             "num_attention_heads": 2}
    config = transformers.Owlv2Config(
        text_config={**layer, "vocab_size": vocab_size, "max_position_embeddings": 16,
                     "bos_token_id": 0, "eos_token_id": 1, "pad_token_id": 1},
        vision_config={**layer, "image_size": image_size, "patch_size": 16},
        projection_dim=32)
    transformers.Owlv2ForObjectDetection(config).save_pretrained(str(out))
    return out


def save_tiny_segmenter(directory: str | Path, *, image_size: int = 64, seed: int = 0) -> Path:
    """Save a random ``SamModel`` (hidden sizes 16–32, one layer, ``image_size`` [px] input) to
    ``directory``; returns it."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    transformers, torch = require("transformers"), require("torch")
    torch.manual_seed(seed)
    config = transformers.SamConfig(
        vision_config={"hidden_size": 32, "intermediate_size": 64, "num_hidden_layers": 1,
                       "num_attention_heads": 2, "image_size": image_size, "patch_size": 16,
                       "output_channels": 16, "window_size": 2, "global_attn_indexes": [0],
                       "mlp_dim": 64, "num_pos_feats": 8},
        prompt_encoder_config={"hidden_size": 16, "image_size": image_size, "patch_size": 16,
                               "mask_input_channels": 4},
        mask_decoder_config={"hidden_size": 16, "mlp_dim": 32, "num_hidden_layers": 1,
                             "num_attention_heads": 2, "iou_head_hidden_dim": 16})
    transformers.SamModel(config).save_pretrained(str(out))
    return out


def save_tiny_models(directory: str | Path, *, image_size: int = 64) -> tuple[Path, Path]:
    """Save a tiny detector and segmenter under ``directory`` (``owlv2/``, ``sam/``); returns
    their directories (detector, segmenter)."""
    root = Path(directory)
    return (save_tiny_detector(root / "owlv2", image_size=image_size),
            save_tiny_segmenter(root / "sam", image_size=image_size))
