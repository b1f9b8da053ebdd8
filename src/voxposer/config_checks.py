"""Range checks of typed configs' fields, one :class:`~voxposer.errors.ConfigError` naming
``<Config>.<field>``, what is allowed and the value given.

Each config's ``__post_init__`` calls these with its own field names::

    require_positive(self, "timestep", "block_size")
    require_int_at_least(self, 1, "rounds")
"""

from __future__ import annotations

import math
from typing import Any

from voxposer.errors import ConfigError


def _number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _fail(config: object, name: str, allowed: str, value: Any) -> ConfigError:
    return ConfigError(f"{type(config).__name__}.{name} must be {allowed}; got {value!r}")


def require_positive(config: object, *names: str) -> None:
    """Each field in ``names`` is a finite number > 0."""
    for name in names:
        value = getattr(config, name)
        if not (_number(value) and value > 0):
            raise _fail(config, name, "a positive finite number", value)


def require_non_negative(config: object, *names: str) -> None:
    """Each field in ``names`` is a finite number >= 0."""
    for name in names:
        value = getattr(config, name)
        if not (_number(value) and value >= 0):
            raise _fail(config, name, "a non-negative finite number", value)


def require_int_at_least(config: object, minimum: int, *names: str) -> None:
    """Each field in ``names`` is an int >= ``minimum``."""
    for name in names:
        value = getattr(config, name)
        if not (isinstance(value, int) and not isinstance(value, bool) and value >= minimum):
            raise _fail(config, name, f"an int >= {minimum}", value)


def require_below(config: object, low: str, high: str) -> None:
    """Field ``low`` is below field ``high``."""
    if not getattr(config, low) < getattr(config, high):
        raise _fail(config, low, f"below {high} ({getattr(config, high)!r})", getattr(config, low))


__all__ = ["require_below", "require_int_at_least", "require_non_negative", "require_positive"]
