"""The attribute allowlist: what generated code may read or call on the objects it holds.

``np.*`` functions and operators are size-checked, but the objects they return have methods of
their own that allocate (``np.zeros(1000).repeat(10**5)`` is 10**8 elements) or run for minutes
in one C call (``a.sort()`` on a huge array, ``a.dot(b)``). So every attribute read in generated
code goes through :meth:`AttributePolicy.get`:

* **numpy arrays and scalars, dtypes, ``np.finfo`` / ``np.iinfo``, random generators, ufuncs
  (``np.add.reduce``), scipy's ``Rotation`` and the builtin types** (str, list, dict, tuple, set,
  int, float, range, slice): only the names on their list below. A method that can allocate
  (``repeat``, ``resize``, ``reshape``, ``astype``, ``copy``, ``flatten``, ``ravel``, ``take``,
  ``cumsum``, ``tolist``, ``nonzero``, ``dot``, ``ufunc.outer``, ``str.join``, ``list.extend``…)
  is returned as a :class:`CheckedMethod` that checks the size of its result before it runs;
  super-linear ones (``dot``, ``sort``, ``argsort``, ``list.sort``) also check their work.
* **Functions, modules, classes and the sandbox's own objects**: nothing (classes: the
  constructors of ``Rotation`` only).
* **The caller's own objects** (given in ``variables``, e.g. detected objects, NamedTuples,
  dataclasses — any type from a module other than builtins, numpy, scipy and the sandbox):
  their public data attributes — values that are not callables, modules or classes — and, for
  mappings, ``get`` / ``keys`` / ``values`` / ``items``.

Anything else raises :class:`voxposer.errors.SandboxError` naming the attribute and listing
what is allowed.
"""

from __future__ import annotations

import dataclasses
import types
from collections.abc import Mapping
from typing import Any, Final, NamedTuple

import numpy as np
from scipy.spatial.transform import Rotation

from voxposer.errors import SandboxError
from voxposer.lmp.sandbox_checks import (
    CheckedMethod,
    Checker,
    check_astype,
    check_dot,
    check_extend,
    check_first_elements,
    check_join,
    check_list_sort,
    check_new_shape,
    check_nonzero,
    check_outer,
    check_random,
    check_replace,
    check_rotation_count,
    check_same_size,
    check_sorting,
    check_with_self,
)
from voxposer.lmp.sandbox_limits import Limits
from voxposer.lmp.sandbox_numpy import GuardedFunction, NumpyProxy
from voxposer.lmp.sandbox_sizes import NUMPY_SIZES


class Rule(NamedTuple):
    """What one kind of object exposes: names (None: read as is) → the check of a method."""

    label: str
    names: Mapping[str, Checker | None]


def _names(plain: str, **checked: Checker) -> dict[str, Checker | None]:
    out: dict[str, Checker | None] = dict.fromkeys(plain.split())
    out.update(checked)
    return out


_ARRAY: Final = _names(
    "shape ndim size dtype T mT real imag itemsize nbytes strides all any argmax argmin max min "
    "mean sum prod std var trace conj conjugate diagonal squeeze swapaxes transpose item fill "
    "searchsorted partition compress is_integer as_integer_ratio",
    reshape=check_new_shape, resize=check_new_shape,
    repeat=check_with_self(NUMPY_SIZES["repeat"]), take=check_with_self(NUMPY_SIZES["take"]),
    astype=check_astype, copy=check_same_size, flatten=check_same_size,
    ravel=check_same_size, tolist=check_same_size, cumsum=check_same_size,
    cumprod=check_same_size, clip=check_same_size, round=check_same_size,
    argpartition=check_same_size, nonzero=check_nonzero, dot=check_dot, sort=check_sorting,
    argsort=check_sorting,
)
_RANDOM: Final = {name: check_random for name in (
    "random", "random_sample", "standard_normal", "standard_exponential", "uniform", "normal",
    "integers", "randint", "rand", "randn", "choice", "permutation", "exponential", "poisson",
    "binomial", "lognormal", "laplace", "logistic", "gamma", "beta", "rayleigh", "geometric",
    "triangular", "multivariate_normal", "bytes", "shuffle", "permuted")}
_STR: Final = _names(
    "capitalize casefold count endswith find index isalnum isalpha isdecimal isdigit islower "
    "isnumeric isspace istitle isupper lower lstrip partition removeprefix removesuffix rfind "
    "rindex rpartition rsplit rstrip split splitlines startswith strip swapcase title upper",
    join=check_join, replace=check_replace)
_NUMBER: Final = "real imag conjugate"
#: numpy and scipy objects (subclasses included: an array is an array).
RULES: Final[tuple[tuple[type | tuple[type, ...], Rule], ...]] = (
    (np.ndarray, Rule("a numpy array", _ARRAY)),
    (np.generic, Rule("a numpy scalar", _ARRAY)),
    (np.dtype, Rule("a numpy dtype", _names("name kind char itemsize str ndim shape type"))),
    ((np.finfo, np.iinfo), Rule("np.finfo/np.iinfo", _names(
        "eps epsneg max min tiny smallest_normal resolution precision bits dtype"))),
    (Rotation, Rule("a Rotation", _names(
        "as_quat as_matrix as_euler as_rotvec as_mrp apply inv magnitude mean single "
        "approx_equal"))),
    ((np.random.Generator, np.random.RandomState), Rule("a random generator", _RANDOM)),
)
#: Builtin types (and subclasses from the controlled modules; a caller's NamedTuple or dict
#: subclass is the caller's object).
BUILTIN_RULES: Final[tuple[tuple[type | tuple[type, ...], Rule], ...]] = (
    (str, Rule("a str", _STR)),
    (list, Rule("a list", _names("append clear copy count index insert pop remove reverse",
                                 extend=check_extend, sort=check_list_sort))),
    (tuple, Rule("a tuple", _names("count index"))),
    (dict, Rule("a dict", _names(
        "clear copy get items keys pop popitem setdefault update values"))),
    (set, Rule("a set", _names(
        "add clear copy difference difference_update discard intersection intersection_update "
        "isdisjoint issubset issuperset pop remove symmetric_difference "
        "symmetric_difference_update union update"))),
    (frozenset, Rule("a frozenset", _names(
        "copy difference intersection isdisjoint issubset issuperset symmetric_difference "
        "union"))),
    (int, Rule("an int", _names(f"{_NUMBER} bit_length bit_count numerator denominator "
                                "as_integer_ratio is_integer"))),
    (float, Rule("a float", _names(f"{_NUMBER} is_integer as_integer_ratio"))),
    (complex, Rule("a complex", _names(_NUMBER))),
    (range, Rule("a range", _names("start stop step count index"))),
    (slice, Rule("a slice", _names("start stop step"))),
)
_ROTATION_CLASS: Final = Rule("Rotation", _names(
    "from_quat from_matrix from_euler from_rotvec from_mrp align_vectors concatenate",
    identity=check_rotation_count, random=check_rotation_count))
_UFUNC: Final = Rule("a numpy ufunc", _names(
    "nin nout nargs identity", reduce=check_first_elements,
    accumulate=check_first_elements, outer=check_outer))
#: Modules whose objects are limited to the lists above (others belong to the caller).
_CONTROLLED_MODULES: Final = ("builtins", "numpy", "scipy", "RestrictedPython",
                              "voxposer.lmp.sandbox")
_MAPPING_READS: Final = frozenset({"get", "keys", "values", "items"})


class AttributePolicy:
    """Resolves ``obj.name`` for generated code (module docs), checking methods via ``limits``."""

    def __init__(self, limits: Limits) -> None:
        self.limits = limits

    def get(self, obj: Any, name: str) -> Any:
        """``obj.name`` if allowed (wrapped in a :class:`CheckedMethod` when it allocates).

        Raises:
            SandboxError: the attribute is not on ``obj``'s list (the message lists it).
        """
        if isinstance(obj, NumpyProxy):
            return getattr(obj, name)
        if isinstance(obj, types.ModuleType):
            raise SandboxError(f"refused: attribute `.{name}` of module {obj.__name__}")
        rule = self._rule(obj)
        if rule is None:
            return _caller_attribute(obj, name)
        if name not in rule.names:
            allowed = ", ".join(sorted(rule.names)) or "none"
            raise SandboxError(f"refused: attribute `.{name}` of {rule.label} is not on the "
                               f"sandbox's allowlist; allowed: {allowed}")
        target = obj._func if isinstance(obj, GuardedFunction) else obj
        value = getattr(target, name)
        check = rule.names[name]
        if check is None:
            return value
        return CheckedMethod(f"{_owner(obj)}.{name}", value, check, self.limits, target)

    @staticmethod
    def _rule(obj: Any) -> Rule | None:
        if isinstance(obj, type):
            if issubclass(obj, Rotation):
                return _ROTATION_CLASS
            return Rule(f"the class {obj.__name__}", {})
        if isinstance(obj, GuardedFunction):
            if isinstance(obj._func, np.ufunc):
                return _UFUNC
            return Rule(f"the function {obj.qualified_name}", {})
        for kind, rule in RULES:
            if isinstance(obj, kind):
                return rule
        module = type(obj).__module__ or ""
        if not module.startswith(_CONTROLLED_MODULES):
            return None
        for kind, rule in BUILTIN_RULES:
            if isinstance(obj, kind):
                return rule
        if module.startswith("voxposer.lmp.sandbox"):
            return Rule(repr(obj), {})
        return Rule(f"a {type(obj).__name__} object", {})


def _owner(obj: Any) -> str:
    if isinstance(obj, GuardedFunction):
        return obj.qualified_name
    return type(obj).__name__ if not isinstance(obj, type) else obj.__name__


def _caller_attribute(obj: Any, name: str) -> Any:
    """A public data attribute of an object the caller gave (or a mapping's read method)."""
    if isinstance(obj, Mapping) and name in _MAPPING_READS:
        return getattr(obj, name)
    value = getattr(obj, name)
    if callable(value) or isinstance(value, types.ModuleType | type):
        if dataclasses.is_dataclass(obj):
            fields = [f.name for f in dataclasses.fields(obj) if not f.name.startswith("_")]
        elif isinstance(obj, tuple) and hasattr(obj, "_fields"):
            fields = list(obj._fields)
        else:
            fields = sorted(k for k in getattr(obj, "__dict__", {}) if not k.startswith("_"))
        extra = ", or get/keys/values/items" if isinstance(obj, Mapping) else ""
        raise SandboxError(
            f"refused: `.{name}` of {type(obj).__name__} is a method; generated code may read "
            f"only the data attributes of the objects it is given ({', '.join(fields) or 'none'}"
            f"{extra})")
    return value
