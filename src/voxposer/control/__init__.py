"""Closed-loop execution of value maps (the paper's ``execute`` and its MPC loop)."""

from voxposer.control.closed_loop import ClosedLoopController, ExecutionResult
from voxposer.control.config import ExecutorConfig

__all__ = ["ClosedLoopController", "ExecutionResult", "ExecutorConfig"]
