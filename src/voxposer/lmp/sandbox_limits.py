"""Size limits for sandboxed code: a numpy proxy and guarded arithmetic.

Generated code may allocate arrays (``np.zeros((10**5,) * 3)``) or sequences (``[0] * 10**10``)
large enough to take the machine down before any time limit fires, because the work happens
inside one C call. These guards compute the size of the result *before* the call and raise
:class:`voxposer.errors.SandboxError` naming the construct when it exceeds the limit.

* :class:`NumpyProxy` exposes numpy to sandboxed code: allocating functions (``zeros``, ``ones``,
  ``full``, ``empty``, ``arange``, ``linspace``, ``tile``, ``repeat``, ``meshgrid``, ``mgrid``…)
  are size-checked, file/OS functions (``load``, ``save``, ``fromfile``, ``memmap``…) and
  submodules other than ``linalg`` and ``random`` are refused.
* :func:`make_binop_guard` checks ``a * b``, ``a ** b``, ``a << b`` and array broadcasting.
"""

from __future__ import annotations

import math
import operator
import types
from collections.abc import Callable, Iterable
from typing import Any, Final

import numpy as np

from voxposer.errors import SandboxError

#: numpy names sandboxed code may never reach (files, OS, raw memory, introspection).
REFUSED_NUMPY: Final = frozenset({
    "load", "save", "savez", "savez_compressed", "savetxt", "loadtxt", "genfromtxt", "fromfile",
    "fromregex", "memmap", "DataSource", "ctypeslib", "lib", "testing", "f2py", "distutils",
    "show_config", "show_runtime", "info", "source", "get_include", "frombuffer", "fromstring",
    "require", "setbufsize", "seterrcall", "add_docstring", "add_newdoc", "byte_bounds",
    "char", "rec", "ma", "polynomial", "typing", "core", "exceptions", "dtypes", "emath",
    "strings", "matlib", "compat", "version", "resize",
})
_SUBMODULES: Final = frozenset({"linalg", "random", "fft"})
_SIZE_WORDS: Final = ("shape", "size", "num", "reps", "repeats", "N", "M")


def _prod(values: Iterable[Any]) -> int:
    out = 1
    for v in values:
        out *= max(int(v), 0)
    return out


def _as_shape(value: Any) -> list[int] | None:
    """A shape-like argument as a list of ints, or None when it is not one."""
    if isinstance(value, bool):
        return None
    if isinstance(value, int | np.integer):
        return [int(value)]
    if isinstance(value, tuple | list) and value and all(
        isinstance(v, int | np.integer) and not isinstance(v, bool) for v in value
    ):
        return [int(v) for v in value]
    return None


def _size(value: Any) -> int:
    return int(np.size(value)) if not isinstance(value, str) else 1


class SizeGuard:
    """Checks result sizes against ``max_elements`` (array elements / sequence items)."""

    def __init__(self, max_elements: int) -> None:
        self.max_elements = int(max_elements)

    def check(self, count: float, what: str) -> None:
        """Raise :class:`SandboxError` when ``count`` elements would exceed the limit."""
        if not math.isfinite(count) or count > self.max_elements:
            raise SandboxError(
                f"size limit: {what} would create {count:.3g} elements; the sandbox allows at "
                f"most {self.max_elements:,} (the value maps have 1,000,000 voxels)"
            )

    def check_call(self, name: str, args: tuple[Any, ...], kwargs: dict[str, Any]) -> None:
        """Estimate the size of ``np.<name>(*args, **kwargs)`` before calling it."""
        what = f"np.{name}(...)"
        if name == "arange":
            nums = [float(a) for a in args if isinstance(a, int | float | np.number)]
            nums += [float(kwargs[k]) for k in ("start", "stop", "step") if k in kwargs]
            if len(nums) == 1:
                self.check(abs(nums[0]), what)
            elif len(nums) >= 2:
                step = nums[2] if len(nums) > 2 else 1.0
                if step == 0:
                    return
                self.check(abs((nums[1] - nums[0]) / step), what)
            return
        if name in ("tile", "repeat") and args:
            reps = args[1] if len(args) > 1 else kwargs.get("reps", kwargs.get("repeats", 1))
            rep_count = int(np.max(reps)) if name == "repeat" else _prod(np.atleast_1d(reps))
            self.check(_size(args[0]) * max(rep_count, 1), what)
            return
        if name in ("meshgrid", "ix_"):
            sizes = [_size(a) for a in args]
            self.check(_prod(sizes) * max(len(sizes), 1), what)
            return
        if name in ("outer", "kron") and len(args) >= 2:
            self.check(_size(args[0]) * _size(args[1]), what)
            return
        if name in ("indices",) and args:
            dims = _as_shape(args[0]) or [0]
            self.check(_prod(dims) * len(dims), what)
            return
        if name == "pad" and len(args) >= 2:
            width = int(np.max(np.abs(np.asarray(args[1], dtype=np.int64)))) if np.size(args[1]) else 0
            dims = np.shape(args[0])
            self.check(_prod([d + 2 * width for d in dims]), what)
            return
        if name in ("eye", "identity", "tri") and args:
            n = int(args[0])
            m = int(args[1]) if len(args) > 1 and isinstance(args[1], int) else n
            self.check(n * m, what)
            return
        # generic: any shape-like positional or size keyword
        for value in list(args) + [kwargs[k] for k in _SIZE_WORDS if k in kwargs]:
            shape = _as_shape(value)
            if shape is not None:
                self.check(_prod(shape), what)


class _GuardedFunction:
    """A numpy callable whose result size is checked before it runs."""

    def __init__(self, name: str, func: Callable[..., Any], guard: SizeGuard) -> None:
        self._name, self._func, self._guard = name, func, guard

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        self._guard.check_call(self._name, args, kwargs)
        return self._func(*args, **kwargs)

    def __repr__(self) -> str:
        return f"<sandboxed np.{self._name}>"


class _GuardedIndexTricks:
    """``np.mgrid`` / ``np.ogrid`` with the size of the slices checked."""

    def __init__(self, name: str, obj: Any, guard: SizeGuard) -> None:
        self._name, self._obj, self._guard = name, obj, guard

    def __getitem__(self, key: Any) -> Any:
        parts = key if isinstance(key, tuple) else (key,)
        sizes = []
        for part in parts:
            if isinstance(part, slice):
                start = 0 if part.start is None else part.start
                step = 1 if part.step is None else part.step
                if isinstance(step, complex):
                    sizes.append(abs(step))
                elif step:
                    sizes.append(abs((part.stop - start) / step))
            else:
                sizes.append(1)
        total = float(np.prod(sizes)) * (len(sizes) if self._name == "mgrid" else 1)
        self._guard.check(total, f"np.{self._name}[...]")
        return self._obj[key]


class NumpyProxy:
    """What sandboxed code sees as ``np`` (and ``numpy``): numpy with limits.

    Attribute reads are resolved on the real module; allocating functions are wrapped by a
    :class:`SizeGuard`, refused names raise :class:`SandboxError`, submodules are proxied.
    Attributes cannot be assigned.
    """

    def __init__(self, module: types.ModuleType, guard: SizeGuard, path: str = "np") -> None:
        object.__setattr__(self, "_module", module)
        object.__setattr__(self, "_guard", guard)
        object.__setattr__(self, "_path", path)

    def __getattr__(self, name: str) -> Any:
        path = f"{self._path}.{name}"
        if name.startswith("_") or name in REFUSED_NUMPY:
            raise SandboxError(f"refused: {path} is not available in generated code")
        value = getattr(self._module, name)
        if isinstance(value, types.ModuleType):
            if name not in _SUBMODULES:
                raise SandboxError(f"refused: the module {path} is not available in generated code")
            return NumpyProxy(value, self._guard, path)
        if name in ("mgrid", "ogrid"):
            return _GuardedIndexTricks(name, value, self._guard)
        if callable(value) and not isinstance(value, type):
            return _GuardedFunction(name, value, self._guard)
        return value

    def __setattr__(self, name: str, value: Any) -> None:
        raise SandboxError(f"refused: assigning {self._path}.{name}")

    def __repr__(self) -> str:
        return f"<sandboxed {self._path}>"


_BINOPS: Final[dict[str, Callable[[Any, Any], Any]]] = {
    "+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv,
    "//": operator.floordiv, "%": operator.mod, "**": operator.pow, "<<": operator.lshift,
    ">>": operator.rshift, "&": operator.and_, "|": operator.or_, "^": operator.xor,
    "@": operator.matmul,
}
_SEQUENCES: Final = (str, bytes, list, tuple)


def make_binop_guard(guard: SizeGuard) -> Callable[[str, Any, Any], Any]:
    """``binop(op, a, b)``: ``a <op> b`` after checking the size of its result.

    Checks sequence repetition (``[0] * n``, ``"x" * n``), huge integer powers and shifts, and
    numpy broadcasting (``a[:, None] * b[None, :]``).
    """

    def binop(op: str, a: Any, b: Any) -> Any:
        op = op.rstrip("=") if op.endswith("=") and op not in ("==",) else op
        func = _BINOPS.get(op)
        if func is None:
            raise SandboxError(f"refused: unknown operator {op!r}")
        if op == "*" and (isinstance(a, _SEQUENCES) or isinstance(b, _SEQUENCES)):
            seq, n = (a, b) if isinstance(a, _SEQUENCES) else (b, a)
            if isinstance(n, int):
                guard.check(len(seq) * max(n, 0), f"repeating a {type(seq).__name__}")
        elif op in ("**", "<<") and isinstance(a, int) and isinstance(b, int) and b > 0:
            bits = b if op == "<<" else b * max(abs(a), 2).bit_length()
            if bits > 65_536:
                raise SandboxError(
                    f"size limit: {a} {op} {b} would be an integer of about {bits:,} bits"
                )
        elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
            try:
                shape = np.broadcast_shapes(np.shape(a), np.shape(b))
            except ValueError:
                shape = ()
            guard.check(_prod(shape), f"the array expression a {op} b")
        return func(a, b)

    return binop
