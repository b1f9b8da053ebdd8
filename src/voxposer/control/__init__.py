"""Closed-loop execution of value maps (the paper's ``execute`` and its MPC loop)."""

from voxposer.control.config import ExecutorConfig
from voxposer.control.executor import ClosedLoopExecutor, ExecutionResult

__all__ = ["ClosedLoopExecutor", "ExecutionResult", "ExecutorConfig"]
