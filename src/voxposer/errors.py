"""One exception hierarchy for the whole package.

Every error a user (or a language model retrying its code) can cause is a subclass of
:class:`VoxPoserError`. Messages name the offending value and what is allowed, because the same
text is shown on the terminal and fed back to the LLM during self-correction.
"""

from __future__ import annotations

from collections.abc import Iterable


class VoxPoserError(Exception):
    """Base class of every error raised on purpose by voxposer."""


class ConfigError(VoxPoserError, ValueError):
    """A configuration field has a value outside its allowed range."""


class GridError(VoxPoserError, ValueError):
    """A workspace grid was defined with invalid bounds or shape."""


class OutOfWorkspaceError(VoxPoserError, ValueError):
    """A point or voxel lies outside the workspace grid."""


class InvalidMapError(VoxPoserError, ValueError):
    """A value map has the wrong shape or dtype, or holds NaN/inf."""


class EmptyAffordanceError(InvalidMapError):
    """An affordance map has no positive voxel, so nothing attracts the entity."""


class PlanningError(VoxPoserError):
    """The motion planner could not produce a path."""


class StartBlockedError(PlanningError):
    """The start voxel is enclosed by obstacles: there is nowhere to go."""


class TargetUnreachableError(PlanningError):
    """No collision-free path connects the start to any affordance target voxel."""


class UnknownObjectError(VoxPoserError, KeyError):
    """An object name is not in the scene; the message lists the scene's names."""

    def __init__(self, name: str, known: Iterable[str]) -> None:
        self.name = name
        self.known = sorted(known)
        super().__init__(name)

    def __str__(self) -> str:
        return f"unknown object {self.name!r}; the scene has: {', '.join(self.known)}"


class MissingAssetError(VoxPoserError, FileNotFoundError):
    """A model asset (e.g. the Panda meshes from the robosuite wheel) cannot be found."""


class LayoutError(VoxPoserError, ValueError):
    """A scene layout cannot be realised (unknown object, no free space to place it)."""


class ObjectNotVisibleError(VoxPoserError):
    """An object is in the scene but no camera sees any of its points."""


class UnreachablePoseError(VoxPoserError):
    """No joint configuration reaches the requested end-effector pose.

    Attributes:
        position: the requested position [m], shape (3,).
        position_error: distance [m] from the closest reachable pose found to the target.
        rotation_error: angle [rad] between the closest reachable orientation and the target.
    """

    def __init__(self, position: object, position_error: float, rotation_error: float) -> None:
        self.position = position
        self.position_error = float(position_error)
        self.rotation_error = float(rotation_error)
        super().__init__(
            f"end-effector pose at {position} m is unreachable; the closest reachable pose is "
            f"{self.position_error * 100:.1f} cm and {self.rotation_error:.3f} rad away"
        )


class MoveMissedError(VoxPoserError):
    """A move ended away from its target (blocked, or stopped by the settle time).

    Attributes:
        position: the requested position [m], shape (3,).
        position_error: final distance [m] to the target.
        rotation_error: final angle [rad] to the target orientation.
    """

    def __init__(self, position: object, position_error: float, rotation_error: float) -> None:
        self.position = position
        self.position_error = float(position_error)
        self.rotation_error = float(rotation_error)
        super().__init__(
            f"the move to {position} m ended {self.position_error * 100:.1f} cm and "
            f"{self.rotation_error:.3f} rad from its target (blocked?)"
        )


class InvalidActionError(VoxPoserError, ValueError):
    """An action is NaN/inf, has the wrong shape, or lies outside its allowed range."""


class SimulationUnstableError(VoxPoserError):
    """The physics state became NaN/inf or diverged; call ``reset`` before stepping again."""


class LLMError(VoxPoserError):
    """A language model backend failed (not configured, unreachable, or kept failing)."""


class ModelNotInstalledError(LLMError):
    """No model is configured and the bundled default model is not installed."""


class SandboxError(VoxPoserError):
    """Generated code used a refused construct, or exceeded a time or size limit."""


class ProgramError(VoxPoserError):
    """A language model program's code failed (after any retries); carries the last attempt."""


class EndpointError(LLMError):
    """An LLM endpoint kept failing (unreachable, timing out, or answering an error status).

    Attributes:
        url: the endpoint's base URL.
        model: the model requested.
        status: the last HTTP status code (None when no response arrived: refused, timed out).
        attempts: how many requests were made before giving up.
    """

    def __init__(
        self, message: str, *, url: str, model: str, status: int | None, attempts: int
    ) -> None:
        self.url = url
        self.model = model
        self.status = status
        self.attempts = attempts
        super().__init__(message)


class ModelIntegrityError(LLMError):
    """An assembled or configured model file is incomplete or fails its sha256 check."""


class ResultError(VoxPoserError, ValueError):
    """A language model program ran but its result is missing or fails a sanity check
    (a map left unchanged, a velocity scale out of range…)."""


class LMPFailedError(ProgramError):
    """A language model program kept failing; ``attempts`` holds every (code, error) tried.

    Attributes:
        lmp: the LMP's name, e.g. "get_affordance_map".
        query: the query it was given.
        attempts: one ``{"code": str, "error": str}`` per attempt, in order.
    """

    def __init__(self, lmp: str, query: str, attempts: list[dict[str, str]]) -> None:
        self.lmp = lmp
        self.query = query
        self.attempts = list(attempts)
        last = attempts[-1]["error"] if attempts else "no attempt"
        super().__init__(f"{lmp}({query!r}) failed after {len(attempts)} attempt(s); last error: "
                         f"{last}")


class ExecutionFailedError(VoxPoserError):
    """Closed-loop execution of a sub-task ended without reaching its target (says why)."""

    def __init__(self, subtask: str, reason: str, message: str) -> None:
        self.subtask = subtask
        self.reason = reason
        super().__init__(f"sub-task {subtask!r} failed ({reason}): {message}")
