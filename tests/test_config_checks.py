"""The shared range checks of typed configs: one error naming <Config>.<field>, the rule, the value."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import pytest

from voxposer.config_checks import (
    require_below,
    require_int_at_least,
    require_non_negative,
    require_positive,
)
from voxposer.errors import ConfigError


@dataclass
class _Settings:
    rate_hz: float = 5.0
    margin_m: float = 0.0
    rounds: int = 3
    low_m: float = 0.01
    high_m: float = 0.12


@pytest.mark.parametrize(("field", "value", "check", "message"), [
    ("rate_hz", 0.0, lambda c: require_positive(c, "rate_hz"), "_Settings.rate_hz must be a positive finite number; got 0.0"),
    ("rate_hz", math.inf, lambda c: require_positive(c, "rate_hz"), "_Settings.rate_hz must be a positive finite number; got inf"),
    ("rate_hz", True, lambda c: require_positive(c, "rate_hz"), "_Settings.rate_hz must be a positive finite number; got True"),
    ("margin_m", -0.1, lambda c: require_non_negative(c, "margin_m"), "_Settings.margin_m must be a non-negative finite number; got -0.1"),
    ("rounds", 2.0, lambda c: require_int_at_least(c, 1, "rounds"), "_Settings.rounds must be an int >= 1; got 2.0"),
    ("low_m", 0.2, lambda c: require_below(c, "low_m", "high_m"), "_Settings.low_m must be below high_m (0.12); got 0.2"),
])
def test_a_value_out_of_range_is_one_error_naming_it(field, value, check, message) -> None:
    settings = _Settings(**{field: value})
    with pytest.raises(ConfigError, match=f"^{re.escape(message)}$"):
        check(settings)


def test_values_in_range_pass() -> None:
    s = _Settings()
    require_positive(s, "rate_hz")
    require_non_negative(s, "margin_m")
    require_int_at_least(s, 0, "rounds")
    require_below(s, "low_m", "high_m")
