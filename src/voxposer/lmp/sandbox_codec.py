"""How values cross between the parent and the sandbox worker: data by value, the rest by handle.

One message is pickled with a *persistent id* hook that takes out what must not be pickled as is:

* numpy arrays: small ones (< :data:`INLINE_BYTES`) as bytes in the message, large ones written
  into the sender's shared-memory arena (:mod:`voxposer.lmp.sandbox_shm`); both keep dtype,
  shape and the read-only flag (a detected object's arrays stay read-only in the worker);
* numpy scalars and scipy ``Rotation`` objects, rebuilt from their numbers;
* everything that is not plain data (functions, the LMP callables, programs, scenes…): a
  *handle*, an index into the parent's table of this run. The worker sees a proxy
  (:mod:`voxposer.lmp.remote`) that calls back into the parent; a proxy sent back is the
  original object again.

Plain data is ``None``, bool, int, float, complex, str, bytes, list, tuple, dict, set, frozenset,
slice, range and the value classes :data:`VALUE_TYPES` (detected objects). The worker may send
nothing else: what it sends is unpickled by :class:`RestrictedUnpickler`, which loads no class
outside that list, because the worker runs untrusted code and must not be able to make the
parent import or call anything.
"""

from __future__ import annotations

import builtins
import io
import pickle
import sys
from collections.abc import Callable
from typing import Any, Final, NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from voxposer.errors import SandboxError
from voxposer.lmp.object_view import ObjectView
from voxposer.lmp.sandbox_shm import aligned, read_array, write_array
from voxposer.perception.detect import DetectedObject

#: Arrays smaller than this [bytes] travel inside the message; larger ones through the arena.
INLINE_BYTES: Final = 64 * 1024
#: Classes whose instances cross by value, field by field (both directions).
VALUE_TYPES: Final = (ObjectView, DetectedObject)
DATA_TYPES: Final = frozenset({type(None), bool, int, float, complex, str, bytes, list, tuple,
                               dict, set, frozenset, slice, range})
_LOADABLE: Final = {("builtins", t.__name__) for t in DATA_TYPES if t is not type(None)} | {
    (t.__module__, t.__qualname__) for t in VALUE_TYPES}
#: Modules whose exception classes a message may name (those already imported).
_EXCEPTION_MODULES: Final = ("builtins", "voxposer", "numpy", "scipy", "RestrictedPython")


class NotTransferable(TypeError):
    """A value that cannot leave the worker (a function the generated code defined, …)."""


class Encoder:
    """Collects the arrays of one outgoing message; subclasses decide what else is data.

    Args:
        plain: further classes pickled as they are (the parent's own messages only).

    Attributes:
        arrays: (offset [bytes], array) of every array bound for the arena, in order.
        nbytes: arena space they take [bytes].
    """

    def __init__(self, plain: tuple[type, ...] = ()) -> None:
        self._plain = plain
        self.arrays: list[tuple[int, NDArray]] = []
        self.nbytes = 0
        self._ids: dict[int, tuple[Any, ...]] = {}
        self._keep: list[Any] = []  # ids stay unique while the message is built

    def dumps(self, value: Any) -> bytes:
        """``value`` pickled with the hook (arrays are recorded, not yet written)."""
        out = io.BytesIO()
        pickler = pickle.Pickler(out, protocol=5)
        pickler.persistent_id = self.persistent_id  # type: ignore[method-assign]
        pickler.dump(value)
        return out.getvalue()

    def write(self, buf: memoryview) -> None:
        """Copy the recorded arrays into the arena ``buf`` (at least :attr:`nbytes` long)."""
        for offset, arr in self.arrays:
            write_array(buf, offset, arr)

    def persistent_id(self, obj: Any) -> tuple[Any, ...] | None:
        kind = type(obj)
        if kind in DATA_TYPES or kind in VALUE_TYPES or kind in self._plain:
            return None
        if isinstance(obj, type):  # classes are pickled by reference: only the data types
            return None if self.is_data_class(obj) else self.other(obj)
        if isinstance(obj, np.ndarray):
            return self._array(obj)
        if isinstance(obj, np.generic) and not obj.dtype.hasobject:
            return ("g", obj.dtype.str, obj.tobytes())
        if isinstance(obj, Rotation):
            return ("rot", obj.as_quat().tolist(), bool(obj.single))
        return self.other(obj)

    def is_data_class(self, cls: type) -> bool:
        """Whether a class object may be pickled by reference (a data or value type)."""
        return cls in DATA_TYPES or cls in VALUE_TYPES or cls in self._plain

    def other(self, obj: Any) -> tuple[Any, ...] | None:
        """The persistent id of a value that is not data (a handle), or None to pickle it."""
        raise NotTransferable(f"a {type(obj).__name__} cannot cross into or out of the worker")

    def _array(self, arr: NDArray) -> tuple[Any, ...]:
        if arr.dtype.hasobject or arr.dtype.fields is not None:
            return self.other(arr)  # type: ignore[return-value]
        key = id(arr)
        if key not in self._ids:
            self._keep.append(arr)
            writeable = bool(arr.flags.writeable)
            head = (arr.dtype.str, tuple(int(n) for n in arr.shape), writeable)
            if arr.nbytes < INLINE_BYTES:
                self._ids[key] = ("a", *head, np.ascontiguousarray(arr).tobytes())
            else:
                self._ids[key] = ("A", *head, self.nbytes)
                self.arrays.append((self.nbytes, arr))
                self.nbytes += aligned(arr.nbytes)
        return self._ids[key]


class Decoder(pickle.Unpickler):
    """Unpickles one blob of a message; arrays come from ``arena``, handles from ``handle``.

    Args:
        data: the pickled blob.
        arena: the sender's arena (None: the message has no arena arrays).
        handle: persistent id ``("h", ...)`` → object.
        restricted: load only plain data and :data:`VALUE_TYPES` (what the worker sends).
    """

    def __init__(self, data: bytes, arena: memoryview | None,
                 handle: Callable[[tuple[Any, ...]], Any], restricted: bool) -> None:
        super().__init__(io.BytesIO(data))
        self._arena = arena
        self._handle = handle
        self._restricted = restricted
        self._arrays: dict[int, NDArray] = {}

    def share_arrays(self, arrays: dict[int, NDArray]) -> None:
        """Use ``arrays`` (offset → array) as the cache, so blobs of one message share arrays."""
        self._arrays = arrays

    def find_class(self, module: str, name: str) -> Any:
        if self._restricted and (module, name) not in _LOADABLE:
            raise pickle.UnpicklingError(f"the sandbox worker sent a refused type "
                                         f"{module}.{name}")
        return super().find_class(module, name)

    def persistent_load(self, pid: Any) -> Any:
        if not isinstance(pid, tuple) or not pid or not isinstance(pid[0], str):
            raise pickle.UnpicklingError(f"malformed persistent id {pid!r}")
        tag = pid[0]
        if tag in ("a", "A"):
            return self._load_array(pid)
        if tag == "g":
            return np.frombuffer(pid[2], _dtype(pid[1]), 1)[0]
        if tag == "rot":
            return Rotation.from_quat(np.asarray(pid[1], dtype=np.float64).reshape(
                (4,) if pid[2] else (-1, 4)))
        if tag == "h":
            return self._handle(pid)
        raise pickle.UnpicklingError(f"unknown persistent id tag {tag!r}")

    def _load_array(self, pid: tuple[Any, ...]) -> NDArray:
        tag, dtype_str, shape, writeable, where = pid
        dtype, shape = _dtype(dtype_str), tuple(int(n) for n in shape)
        if tag == "a":
            arr = read_array(memoryview(where), 0, dtype, shape)
        else:
            if self._arena is None:
                raise pickle.UnpicklingError("an arena array in a message without an arena")
            if int(where) not in self._arrays:
                self._arrays[int(where)] = read_array(self._arena, int(where), dtype, shape)
            arr = self._arrays[int(where)]
        if not writeable:
            arr.flags.writeable = False
        return arr


def _dtype(text: Any) -> np.dtype:
    dtype = np.dtype(str(text))
    if dtype.hasobject or dtype.fields is not None:
        raise pickle.UnpicklingError(f"refused array dtype {text!r}")
    return dtype


# ---------------------------------------------------------------------------- exceptions
class ExceptionInfo(NamedTuple):
    """An exception as it crosses: class, ``args``, public attributes, message, origin.

    ``origin`` is the index of the parent's own exception object when this one is it, coming
    back (a trusted callback raised it and the generated code did not catch it).
    """

    module: str
    qualname: str
    args: tuple[Any, ...]
    attrs: dict[str, Any]
    message: str
    origin: int | None = None


def exception_info(exc: BaseException, origin: int | None = None) -> tuple[Any, ...]:
    """``exc`` as a plain tuple (:class:`ExceptionInfo` fields); attributes are not checked."""
    attrs = {k: v for k, v in getattr(exc, "__dict__", {}).items() if not k.startswith("_")}
    kind = type(exc)
    return (kind.__module__, kind.__qualname__, tuple(exc.args), attrs, str(exc), origin)


def encode_exception(encoder: Encoder, exc: BaseException, origin: int | None = None) -> bytes:
    """``exc`` pickled by ``encoder``: with its args and attributes where they can cross,
    else with its message only."""
    info = exception_info(exc, origin)
    try:
        return encoder.dumps(info)
    except (NotTransferable, pickle.PicklingError, TypeError, AttributeError):
        return encoder.dumps((*info[:2], (info[4],), {}, info[4], origin))


def rebuild_exception(raw: Any) -> BaseException:
    """The exception a decoded :func:`exception_info` tuple describes.

    Classes come only from already-imported modules of :data:`_EXCEPTION_MODULES` and must be
    ``Exception`` subclasses; anything else becomes a :class:`SandboxError` naming the type.
    """
    info = ExceptionInfo(*raw)
    cls = _exception_class(str(info.module), str(info.qualname))
    args = tuple(info.args) if isinstance(info.args, tuple | list) else (str(info.message),)
    if cls is None:
        return SandboxError(f"{info.qualname}: {info.message}")
    try:
        exc = cls(*args)
    except Exception:  # a constructor with another signature (UnknownObjectError(name, known))
        exc = cls.__new__(cls)
        exc.args = args
    if isinstance(info.attrs, dict) and hasattr(exc, "__dict__"):
        exc.__dict__.update({str(k): v for k, v in info.attrs.items()})
    return exc


def _exception_class(module: str, qualname: str) -> type[Exception] | None:
    if not module.startswith(_EXCEPTION_MODULES) or module not in sys.modules:
        return None
    obj: Any = builtins if module == "builtins" else sys.modules[module]
    for part in qualname.split("."):
        if part.startswith("_") and part != qualname.split(".")[-1]:
            return None
        obj = getattr(obj, part, None)
    if isinstance(obj, type) and issubclass(obj, Exception):
        return obj
    return None
