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


class UnresolvedObjectError(UnknownObjectError):
    """A program's object query names no object of the scene, and the program gave up on it
    (after its self-correction); enclosing programs pass it on without retrying, so it reaches
    the user as it is.

    Attributes:
        name: the object name (or query) that matched nothing.
        known: the scene's object names, sorted.
        lmp: the LMP that gave up, e.g. "parse_query_obj".
        query: the query it was given.
        attempts: one ``{"code": str, "error": str}`` per attempt, in order.
    """

    def __init__(self, name: str, known: Iterable[str], *, lmp: str, query: str,
                 attempts: list[dict[str, str]]) -> None:
        super().__init__(name, known)
        self.lmp = lmp
        self.query = query
        self.attempts = list(attempts)

    def __str__(self) -> str:
        return (f"{super().__str__()} ({self.lmp}({self.query!r}) gave up after "
                f"{len(self.attempts)} attempt(s))")


class MissingAssetError(VoxPoserError, FileNotFoundError):
    """A model asset (e.g. the Panda meshes from the robosuite wheel) cannot be found."""


class LayoutError(VoxPoserError, ValueError):
    """A scene layout cannot be realised (unknown object, no free space to place it)."""


class ObjectNotVisibleError(VoxPoserError):
    """An object is in the scene but no camera sees any of its points."""


class _PoseError(VoxPoserError):
    """A pose the robot did not get to: the target and how far off it stayed.

    Attributes:
        position: the requested position [m], shape (3,).
        position_error: distance [m] between the pose got to (or the closest reachable one)
            and the target.
        rotation_error: angle [rad] between that orientation and the target's.
    """

    def __init__(self, position: object, position_error: float, rotation_error: float,
                 message: str) -> None:
        self.position = position
        self.position_error = float(position_error)
        self.rotation_error = float(rotation_error)
        super().__init__(message.format(position=position, cm=self.position_error * 100,
                                        rad=self.rotation_error))


class UnreachablePoseError(_PoseError):
    """No joint configuration reaches the requested end-effector pose (the robot did not move);
    the errors are those of the closest reachable pose found."""

    def __init__(self, position: object, position_error: float, rotation_error: float) -> None:
        super().__init__(position, position_error, rotation_error,
                         "end-effector pose at {position} m is unreachable; the closest "
                         "reachable pose is {cm:.1f} cm and {rad:.3f} rad away")


class MoveMissedError(_PoseError):
    """A move ended away from its target (blocked, or stopped by the settle time); the errors
    are those of where it ended."""

    def __init__(self, position: object, position_error: float, rotation_error: float) -> None:
        super().__init__(position, position_error, rotation_error,
                         "the move to {position} m ended {cm:.1f} cm and {rad:.3f} rad from its "
                         "target (blocked?)")


class NoRobotError(VoxPoserError):
    """A motion was asked of a stand-in robot that has no arm to move (``--robot none``)."""


class InvalidActionError(VoxPoserError, ValueError):
    """An action is NaN/inf, has the wrong shape, or lies outside its allowed range."""


class SimulationUnstableError(VoxPoserError):
    """The physics state became NaN/inf or diverged; call ``reset`` before stepping again."""


class WorkerCrashedError(VoxPoserError):
    """A benchmark worker process died while running an episode (a segfault, an out-of-memory
    kill): its episode is recorded as crashed and the worker replaced."""


class LLMError(VoxPoserError):
    """A language model backend failed (not configured, unreachable, or kept failing)."""


class ModelNotInstalledError(LLMError):
    """No model is configured and the bundled default model is not installed."""


class SandboxError(VoxPoserError):
    """Generated code used a refused construct, or exceeded a time or size limit."""


class VoxelIndexError(SandboxError, IndexError):
    """Generated code indexed a value map outside its grid: a negative voxel index (which numpy
    would silently wrap to the far side of the grid) or one past the end; the message names the
    index, the axis and the array's shape."""


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


class DimensionMismatchError(VoxPoserError, ValueError):
    """Arrays (observations, actions, transitions) or a saved model file have other dimensions
    than a learned dynamics model expects; the message names both shapes."""


class DivergedError(VoxPoserError, ArithmeticError):
    """Training a learned dynamics model produced a NaN/inf loss.

    Attributes:
        epoch: the epoch (from 0) in which the loss stopped being finite.
        loss: the offending loss value.
    """

    def __init__(self, epoch: int, loss: float) -> None:
        self.epoch = int(epoch)
        self.loss = float(loss)
        super().__init__(f"training diverged in epoch {self.epoch}: loss {self.loss!r}; lower "
                         "the learning rate or check the transitions for huge values")


def pending_interrupt(exc: BaseException) -> KeyboardInterrupt | None:
    """The ``KeyboardInterrupt`` (Ctrl-C, a stop signal) behind ``exc``, if any.

    A signal handler that raises while compiled code (a numba kernel) is returning surfaces as a
    ``SystemError`` whose cause is the interrupt. Code that turns a program's exceptions into its
    errors asks this first: an interrupt must stop the run, not count as the program failing.
    """
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        if isinstance(current, KeyboardInterrupt):
            return current
        seen.add(id(current))
        current = current.__cause__ or current.__context__
    return None
