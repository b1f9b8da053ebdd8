"""The instruction as the planner reads it: objects named by relation grounded, distances said
in centimetres — each behind its switch, each change in the transcript."""

from __future__ import annotations

from typing import Any

from voxposer.lmp.quantities import plain_instruction
from voxposer.lmp.references import grounded_instruction
from voxposer.lmp.registry import LMPConfig
from voxposer.lmp.transcript import Transcript


def planner_instruction(instruction: str, scene: Any, config: LMPConfig,
                        transcript: Transcript) -> str:
    """``instruction`` with its relational references grounded on ``scene``
    (``LMPConfig.ground_references``, :mod:`voxposer.lmp.references`) and its distances said
    in centimetres (``LMPConfig.plain_quantities``, :mod:`voxposer.lmp.quantities`)."""
    if config.ground_references:
        instruction = grounded_instruction(instruction, scene, transcript)
    if config.plain_quantities:
        instruction = plain_instruction(instruction, transcript)
    return instruction


__all__ = ["planner_instruction"]
