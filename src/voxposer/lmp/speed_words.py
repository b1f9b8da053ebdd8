"""Speed words: the factor a phrase asks of the robot's default speed, and where it is said.

"at a quarter of the speed" asks 0.25, "3x speed" 3, "half as fast" 0.5, "twice the speed" 2;
a bare direction ("faster", "slowly", "gently") asks 2 or 0.5 — the direction is what a plan
must keep (:mod:`voxposer.lmp.plan_conditions` compares a sub-task's speed with the
instruction's). :func:`speed_span` finds the phrase itself ("at a quarter of the speed"), so a
sub-task that turned it round can be given the instruction's words back.
"""

from __future__ import annotations

import re
from typing import Final

#: what a bare "faster"/"slower" asks [× default speed].
FAST_FACTOR: Final = 2.0
SLOW_FACTOR: Final = 0.5
_FRACTIONS: Final = {"half": 0.5, "quarter": 0.25, "third": 1 / 3, "fifth": 0.2, "tenth": 0.1}
_MULTIPLES: Final = {"twice": 2.0, "double": 2.0, "triple": 3.0, "thrice": 3.0}
_NUMBERS: Final = {"two": 2.0, "three": 3.0, "four": 4.0, "five": 5.0}
_FAST: Final = frozenset({"fast", "faster", "fastest", "quick", "quickly", "quicker", "rapidly",
                          "rapid", "swiftly", "swift", "hurry", "hurried", "brisk", "briskly", "speedily", "higher",
                          "increased", "full", "maximum", "max", "top"})
_SLOW: Final = frozenset({"slow", "slowly", "slower", "slowest", "gently", "carefully",
                          "leisurely", "crawl", "snail", "cautiously", "lower", "reduced", "minimum",
                          "min", "low"})
_SPEED_NOUN: Final = r"(?:speed|pace|velocity)"
#: "3x speed", "3 times faster", "three times as fast", "2.5x slower".
_TIMES: Final = re.compile(r"\b(\d+(?:\.\d+)?|two|three|four|five)\s*(?:x|×|times)(?![a-z])"
                           r"(?:\s+(?:as\s+)?(slower|slow|faster|fast|quicker|quick))?")
#: "a quarter of the speed", "half speed", "half as fast", "one third of its pace".
_FRACTION: Final = re.compile(
    r"\b(half|quarter|third|fifth|tenth)\s+(?:of\s+)?(?:(?:the|its|my|your|the\s+usual|"
    r"the\s+normal|the\s+default|normal|usual|default)\s+)?(?:" + _SPEED_NOUN + r"|as\s+fast|"
    r"as\s+quickly)\b")
_MULTIPLE: Final = re.compile(r"\b(twice|double|triple|thrice)\s+(?:the\s+|its\s+)?"
                              r"(?:" + _SPEED_NOUN + r"|as\s+fast|as\s+quickly)\b")
_ADJECTIVES: Final = "|".join(sorted(_FAST | _SLOW, key=len, reverse=True))
_ADVERBS: Final = "|".join(sorted((_FAST | _SLOW) - {"higher", "increased", "full", "maximum",
                                                     "max", "top", "lower", "reduced",
                                                     "minimum", "min", "low"},
                                  key=len, reverse=True))
#: the phrases a sub-task says its speed with, each with an optional "at a".
_SPANS: Final = tuple(re.compile(r"\b(?:at\s+)?(?:(?:a|an|one)\s+)?(?:" + p + ")") for p in (
    _TIMES.pattern.removeprefix(r"\b") + r"(?:\s+(?:the\s+)?" + _SPEED_NOUN + r"\b)?",
    _FRACTION.pattern.removeprefix(r"\b"),
    _MULTIPLE.pattern.removeprefix(r"\b"),
    r"(?:" + _ADJECTIVES + r")\s+" + _SPEED_NOUN + r"\b",
    r"(?:" + _ADVERBS + r")\b"))


def speed_factor(text: str) -> float | None:
    """The factor of the default speed ``text`` asks (> 1 faster, < 1 slower); None when it
    says nothing of speed."""
    t = " ".join(text.lower().split())
    if m := _TIMES.search(t):
        value = _NUMBERS.get(m.group(1)) or float(m.group(1))
        if value > 0:
            return 1.0 / value if m.group(2) and m.group(2).startswith("slow") else value
    if m := _FRACTION.search(t):
        return _FRACTIONS[m.group(1)]
    if m := _MULTIPLE.search(t):
        return _MULTIPLES[m.group(1)]
    words = set(re.findall(r"[a-z]+", t))
    nouns = {"speed", "pace", "velocity"} & words
    fast = words & (_FAST if nouns else _FAST - {"higher", "increased", "full", "maximum",
                                                 "max", "top", "low"})
    slow = words & (_SLOW if nouns else _SLOW - {"lower", "reduced", "minimum", "min", "low"})
    if fast and not slow:
        return FAST_FACTOR
    if slow and not fast:
        return SLOW_FACTOR
    return None


def speed_span(text: str) -> tuple[int, int] | None:
    """Where in ``text`` its speed phrase is, as (start, end) character offsets; None when
    there is none."""
    found = [m for p in _SPANS if (m := p.search(text.lower()))]
    if not found:
        return None
    best = min(found, key=lambda m: (m.start(), -m.end()))
    return best.start(), best.end()


def same_direction(a: float, b: float) -> bool:
    """Whether two factors ask the same kind of change (both faster, both slower, or both
    the default)."""
    return (a > 1.0) == (b > 1.0) and (a < 1.0) == (b < 1.0)


__all__ = ["FAST_FACTOR", "SLOW_FACTOR", "same_direction", "speed_factor", "speed_span"]
