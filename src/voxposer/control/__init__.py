"""Closed-loop execution of value maps (the paper's ``execute`` and its MPC loop)."""

from voxposer.control.closed_loop import ClosedLoopController
from voxposer.control.config import ExecutorConfig
from voxposer.control.execution_result import ExecutionResult

__all__ = ["ClosedLoopController", "ExecutionResult", "ExecutorConfig"]
