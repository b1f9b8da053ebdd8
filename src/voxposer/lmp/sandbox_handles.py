"""The parent's side of handles: which of the caller's objects the worker gets as proxies.

During one (outermost) run of the process sandbox, every value sent to the worker that is not
plain data (:mod:`voxposer.lmp.sandbox_codec`) is kept in a :class:`Handles` table and sent as
its index; the worker's proxy (:mod:`voxposer.lmp.remote`) names that index when it calls back,
and a proxy sent back decodes to the very object. The methods of the scene-bound ``LMPAPI`` are
sent differently (:func:`prepare`): the worker builds its own API over a proxy of the scene.
"""

from __future__ import annotations

import pickle
import types
from collections.abc import Mapping
from typing import Any

from voxposer.geometry.voxel_grid import VoxelGrid
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.remote import ApiMethod, ApiSpec
from voxposer.lmp.sandbox_codec import Encoder


class Handles:
    """The parent's objects the worker holds proxies of during one (outermost) run."""

    def __init__(self) -> None:
        self.objects: list[Any] = []
        self._index: dict[int, int] = {}

    def add(self, obj: Any) -> int:
        if id(obj) not in self._index:
            self._index[id(obj)] = len(self.objects)
            self.objects.append(obj)
        return self._index[id(obj)]

    def get(self, index: Any) -> Any:
        if not isinstance(index, int) or not 0 <= index < len(self.objects):
            raise pickle.UnpicklingError(f"the sandbox worker named no handle {index!r}")
        return self.objects[index]

    def clear(self) -> None:
        self.objects.clear()
        self._index.clear()


class ParentEncoder(Encoder):
    """Data by value; every other object as a handle the worker sees as a proxy."""

    def __init__(self, handles: Handles) -> None:
        super().__init__(plain=(ApiSpec, ApiMethod, VoxelGrid))
        self._handles = handles

    def other(self, obj: Any) -> tuple[Any, ...]:
        text = repr(obj)
        return ("h", self._handles.add(obj), callable(obj),
                text if len(text) <= 200 else text[:197] + "...")


def prepare(variables: Mapping[str, Any], handles: Handles
        ) -> tuple[dict[str, Any], list[ApiSpec]]:
    """``variables`` with the methods of an ``LMPAPI`` replaced by :class:`ApiMethod`s
    (the worker rebuilds that API on a proxy of its scene), and those APIs' specs."""
    out: dict[str, Any] = dict(variables)
    specs: list[ApiSpec] = []
    index: dict[int, int] = {}
    apis = {id(v.__self__): v.__self__ for v in variables.values()
            if isinstance(v, types.MethodType) and type(v.__self__) is LMPAPI}
    owners = dict(apis)
    owners.update({id(api.maps): api for api in apis.values()})
    for name, value in variables.items():
        if not isinstance(value, types.MethodType) or id(value.__self__) not in owners:
            continue
        api = owners[id(value.__self__)]
        attr = value.__name__ if value.__self__ is api else f"maps.{value.__name__}"
        if id(api) not in index:
            index[id(api)] = len(specs)
            scene = api.scene
            specs.append(ApiSpec(api.grid, tuple(scene.object_names), scene.detect,
                                 scene.ee_pose, scene.gripper_state))
        out[name] = ApiMethod(handles.add(value), index[id(api)], attr)
    return out, specs
