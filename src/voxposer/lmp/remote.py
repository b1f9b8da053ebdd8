"""The caller's objects as the process sandbox's worker sees them: proxies that call back.

In process isolation (:mod:`voxposer.lmp.sandbox_process`) only plain data crosses into the
worker. A callable or any other object of the caller — ``detect`` of a custom perceiver, the LMP
callables (``parse_query_obj``), ``execute``, a :class:`~voxposer.lmp.program.ValueMapProgram` —
arrives as a :class:`RemoteObject` (:class:`RemoteCallable` when it is callable): calling it,
reading a public attribute (``movable.position``) or an item (``movable["position"]``) asks the
parent, which does it on the real object — with the same attribute policy as in-process — and
sends back the result or the exception. Generated code cannot tell the difference, except that
it cannot assign attributes of a proxy.

This module's name deliberately does not start with ``sandbox``: the attribute policy
(:mod:`voxposer.lmp.sandbox_attrs`) treats objects from those modules as the sandbox's own, with
no attributes; a proxy stands for the caller's object and follows the caller's rules.

The scene-bound API (:class:`~voxposer.lmp.api.LMPAPI`) is not proxied method by method: the
worker builds its own ``LMPAPI`` over a :class:`RemoteScene` (an :class:`ApiSpec`), so helpers
that change a map in place (``set_voxel_by_radius``) work on the worker's array, and only the
scene's perception calls cross.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

from voxposer.errors import SandboxError
from voxposer.geometry.voxel_grid import VoxelGrid


class Link(Protocol):
    """The worker's connection to the parent, as proxies use it."""

    def request(self, kind: str, index: int, *payload: Any) -> Any:
        """Send ``kind`` ("call", "getattr", "getitem") about handle ``index``; the result."""


class RemoteObject:
    """An object that stays in the parent (handle ``index`` of the current run)."""

    __slots__ = ("_index", "_link", "_text")

    def __init__(self, link: Link, index: int, text: str) -> None:
        object.__setattr__(self, "_link", link)
        object.__setattr__(self, "_index", index)
        object.__setattr__(self, "_text", text)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):  # numpy and Python probe __array__ & co. on every object
            raise AttributeError(name)
        return self._link.request("getattr", self._index, name)

    def __getitem__(self, key: Any) -> Any:
        return self._link.request("getitem", self._index, key)

    def __setattr__(self, name: str, value: Any) -> None:
        raise SandboxError(f"refused: assigning attribute `.{name}` of {self._text} (an "
                           "object outside the sandbox)")

    def __repr__(self) -> str:
        return self._text


class RemoteCallable(RemoteObject):
    """A callable that stays in the parent: a call runs there (its time is not counted)."""

    __slots__ = ()

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self._link.request("call", self._index, args, kwargs)


@dataclass(frozen=True)
class ApiSpec:
    """What the worker needs to build an ``LMPAPI`` of the parent's scene.

    Attributes:
        grid: the scene's workspace grid (by value).
        object_names: the scene's object names when the run started (by value: one round trip
            less per ``detect``).
        detect, ee_pose, gripper_state: the scene's methods (proxies in the worker).
    """

    grid: VoxelGrid
    object_names: tuple[str, ...]
    detect: Any
    ee_pose: Any
    gripper_state: Any


@dataclass(frozen=True)
class ApiMethod:
    """A variable that is a method of an ``LMPAPI`` (``attr``: "detect", "maps.pointat2quat").

    Attributes:
        handle: the parent's handle of the original bound method (what goes back).
        api: index of the :class:`ApiSpec` in the run's list.
        attr: the method's path on the ``LMPAPI``.
    """

    handle: int
    api: int
    attr: str


class RemoteScene:
    """The :class:`~voxposer.lmp.scene.Scene` protocol over an :class:`ApiSpec` in the worker."""

    def __init__(self, spec: ApiSpec) -> None:
        self._spec = spec

    @property
    def grid(self) -> VoxelGrid:
        return self._spec.grid

    @property
    def object_names(self) -> tuple[str, ...]:
        return self._spec.object_names

    def detect(self, name: str) -> Any:
        return self._spec.detect(name)

    def ee_pose(self) -> Any:
        return self._spec.ee_pose()

    def gripper_state(self) -> float:
        return float(self._spec.gripper_state())
