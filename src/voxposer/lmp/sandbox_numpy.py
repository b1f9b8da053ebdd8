"""numpy as sandboxed code sees it: a proxy whose functions are size- and work-checked.

* :class:`NumpyProxy` is ``np`` (and ``numpy``) inside generated code: every function is wrapped
  in a :class:`GuardedFunction` that checks the size of its result
  (:mod:`voxposer.lmp.sandbox_sizes`) and, for super-linear ones, its work
  (:mod:`voxposer.lmp.sandbox_work`) before calling it; file/OS functions (``load``, ``save``,
  ``fromfile``, ``memmap``…) and submodules other than ``linalg``, ``random`` and ``fft`` are
  refused; ``np.mgrid`` / ``np.ogrid`` / ``np.r_`` / ``np.c_`` check their slices.
* What the functions return (arrays, scalars, generators of random numbers…) is limited by the
  attribute allowlist of :mod:`voxposer.lmp.sandbox_attrs`.
"""

from __future__ import annotations

import types
from collections.abc import Callable
from typing import Any, Final

import numpy as np

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox_limits import Limits
from voxposer.lmp.sandbox_work import elements

#: numpy names sandboxed code may never reach (files, OS, raw memory, introspection).
REFUSED_NUMPY: Final = frozenset({
    "load", "save", "savez", "savez_compressed", "savetxt", "loadtxt", "genfromtxt", "fromfile",
    "fromregex", "memmap", "DataSource", "ctypeslib", "lib", "testing", "f2py", "distutils",
    "show_config", "show_runtime", "info", "source", "get_include", "frombuffer", "fromstring",
    "require", "setbufsize", "seterrcall", "add_docstring", "add_newdoc", "byte_bounds",
    "char", "rec", "ma", "polynomial", "typing", "core", "exceptions", "dtypes", "emath",
    "strings", "matlib", "compat", "version", "resize",
})
SUBMODULES: Final = frozenset({"linalg", "random", "fft"})
#: Classes whose constructor allocates (``np.ndarray((10**5,) * 3)``).
ALLOCATING_CLASSES: Final = frozenset({"ndarray", "matrix", "recarray"})


class GuardedFunction:
    """A numpy callable whose result size (and work) is checked before it runs.

    Args:
        path: where it lives as generated code sees it ("np", "np.linalg"…).
        name: its name there.
        func: the numpy callable (kept private: generated code cannot reach it).
    """

    def __init__(self, path: str, name: str, func: Callable[..., Any], limits: Limits) -> None:
        self._path, self._name, self._func, self._limits = path, name, func, limits

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        self._limits.size.check_call(self._name, args, kwargs, path=self._path, func=self._func)
        self._limits.work.check_call(self._path, self._name, args, kwargs)
        return self._func(*args, **kwargs)

    @property
    def qualified_name(self) -> str:
        """``"np.linalg.inv"``, as generated code spells it."""
        return f"{self._path}.{self._name}"

    def __repr__(self) -> str:
        return f"<sandboxed {self.qualified_name}>"


class GuardedClass:
    """An allocating numpy class: calling it is size-checked; ``isinstance(x, np.ndarray)`` and
    ``issubclass`` still work."""

    def __init__(self, name: str, cls: type, limits: Limits) -> None:
        self._name, self._cls, self._limits = name, cls, limits

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        self._limits.size.check_call(self._name, args, kwargs)
        return self._cls(*args, **kwargs)

    def __instancecheck__(self, obj: Any) -> bool:
        return isinstance(obj, self._cls)

    def __subclasscheck__(self, cls: type) -> bool:
        return issubclass(cls, self._cls)

    def __repr__(self) -> str:
        return f"<sandboxed np.{self._name}>"


class GuardedIndexTricks:
    """``np.mgrid`` / ``np.ogrid`` / ``np.r_`` / ``np.c_`` with the size of their slices checked.

    ``mgrid`` creates the product of the slice lengths per dimension; ``ogrid`` the product;
    ``r_`` / ``c_`` join their parts, so they create the sum.
    """

    def __init__(self, name: str, obj: Any, limits: Limits) -> None:
        self._name, self._obj, self._limits = name, obj, limits

    def __getitem__(self, key: Any) -> Any:
        parts = key if isinstance(key, tuple) else (key,)
        sizes = [_part_length(part) for part in parts]
        if self._name in ("r_", "c_"):
            total = float(sum(sizes))
        else:
            total = float(np.prod(sizes)) * (len(sizes) if self._name == "mgrid" else 1)
        self._limits.size.check(total, f"np.{self._name}[...]")
        return self._obj[key]

    def __repr__(self) -> str:
        return f"<sandboxed np.{self._name}>"


def _part_length(part: Any) -> float:
    """Elements one part of an index-trick key stands for."""
    if isinstance(part, slice):
        start = 0 if part.start is None else part.start
        step = 1 if part.step is None else part.step
        if isinstance(step, complex):
            return abs(step)
        if not step or part.stop is None:
            return 1.0
        return abs((part.stop - start) / step)
    if isinstance(part, str):
        return 0.0
    return float(elements(part))


class NumpyProxy:
    """What sandboxed code sees as ``np`` (and ``numpy``): numpy with limits.

    Attribute reads are resolved on the real module; callables are wrapped in
    :class:`GuardedFunction`, allocating classes in :class:`GuardedClass`, refused names raise
    :class:`SandboxError`, submodules are proxied. Other classes (``np.float64``) and constants
    are returned as they are. Attributes cannot be assigned.
    """

    def __init__(self, module: types.ModuleType, limits: Limits, path: str = "np") -> None:
        object.__setattr__(self, "_module", module)
        object.__setattr__(self, "_limits", limits)
        object.__setattr__(self, "_path", path)

    def __getattr__(self, name: str) -> Any:
        path = f"{self._path}.{name}"
        if name.startswith("_") or name in REFUSED_NUMPY:
            raise SandboxError(f"refused: {path} is not available in generated code")
        value = getattr(self._module, name)
        if isinstance(value, types.ModuleType):
            if name not in SUBMODULES:
                raise SandboxError(f"refused: the module {path} is not available in generated "
                                   f"code; the allowed submodules are "
                                   f"{', '.join(f'np.{m}' for m in sorted(SUBMODULES))}")
            return NumpyProxy(value, self._limits, path)
        if name in ("mgrid", "ogrid", "r_", "c_"):
            return GuardedIndexTricks(name, value, self._limits)
        if name in ALLOCATING_CLASSES and self._path == "np":
            return GuardedClass(name, value, self._limits)
        if callable(value) and not isinstance(value, type):
            return GuardedFunction(self._path, name, value, self._limits)
        return value

    def __setattr__(self, name: str, value: Any) -> None:
        raise SandboxError(f"refused: assigning {self._path}.{name}")

    def __repr__(self) -> str:
        return f"<sandboxed {self._path}>"
