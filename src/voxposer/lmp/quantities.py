"""Distances said in words or other units, said plainly in centimetres before the planner reads them.

The programs' helpers and post-conditions take centimetres (``cm=5``), and the bundled 1.5B
model copies a number it is given far more reliably than it converts one: "roughly two
inches", "five centimetres", "a hand's width" reach the planner as "roughly 5.1 cm", "5 cm",
"10.2 cm". What is rewritten:

- a number (digits or words up to twenty, "and a half", "one and a half") with a unit of
  length: centimetres, millimetres, metres, inches (2.54 cm), feet (30.48 cm);
  "an inch and a half", "half an inch";
- a body measure, by the old units named after it: a hand's width (a hand, 4 in), a palm's
  width (3 in), a finger's or a thumb's width (a digit, ¾ in), a finger's length (4½ in);
- "a few centimetres" (3 cm), "a couple of centimetres" (2 cm).

Qualifiers stay as said ("about", "a little over", "or so"). Values are rounded to 0.1 cm.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Final

from voxposer.lmp.transcript import Transcript

#: unit → centimetres per unit.
UNITS_CM: Final[dict[str, float]] = {
    "cm": 1.0, "centimeter": 1.0, "centimetre": 1.0, "mm": 0.1, "millimeter": 0.1,
    "millimetre": 0.1, "meter": 100.0, "metre": 100.0, "inch": 2.54, "foot": 30.48,
    "feet": 30.48, "ft": 30.48}
#: (body part, width or length) → centimetres (the old units: hand 4 in, palm 3 in, digit
#: ¾ in, finger 4½ in); "breadth" is read as "width".
MEASURES_CM: Final[dict[tuple[str, str], float]] = {
    ("hand", "width"): 10.16, ("palm", "width"): 7.62, ("finger", "width"): 1.905,
    ("thumb", "width"): 1.905, ("finger", "length"): 11.43}
#: vague counts of centimetres.
FEW_CM: Final[dict[str, float]] = {"few": 3.0, "couple of": 2.0, "couple": 2.0}
_WORDS: Final = ("zero one two three four five six seven eight nine ten eleven twelve "
                 "thirteen fourteen fifteen sixteen seventeen eighteen nineteen twenty").split()
_NUMBER_WORDS: Final[dict[str, float]] = {w: float(i) for i, w in enumerate(_WORDS)} | {
    "a": 1.0, "an": 1.0, "half a": 0.5, "half an": 0.5}
_UNIT: Final = (r"(?P<unit>centimet(?:er|re)s?|millimet(?:er|re)s?|met(?:er|re)s?|inch(?:es)?|"
                r"feet|foot|cm|mm|ft)(?![a-z])")
_NUM: Final = (r"(?P<num>\d+(?:\.\d+)?|half an?|" + "|".join(sorted(_WORDS, key=len, reverse=True))
               + r"|an?)(?P<half> and a half)?")
_PATTERNS: Final = (
    re.compile(rf"\b{_NUM}(?: or so)?[ -]?{_UNIT}(?P<half2> and a half)?", re.IGNORECASE),
    re.compile(r"\b(?:a|one) (?P<measure>hand|palm|finger|thumb)(?:'s|s')? "
               r"(?P<dim>width|breadth|length)\b", re.IGNORECASE),
    re.compile(r"\ba (?P<few>few|couple of|couple) (?:centimet(?:er|re)s|cm)\b", re.IGNORECASE),
)


@dataclass(frozen=True)
class Plain:
    """One quantity said plainly: the words said and the centimetres they became."""

    said: str
    cm: float

    def to_json(self) -> dict[str, Any]:
        return {"said": self.said, "cm": self.cm}


def _unit_cm(unit: str) -> float:
    u = unit.lower()
    for key in sorted(UNITS_CM, key=len, reverse=True):
        if u.startswith(key) and (len(key) > 2 or u == key):
            return UNITS_CM[key]
    return UNITS_CM[u.rstrip("s")]


def _value(match: re.Match[str]) -> float | None:
    g = match.groupdict()
    if g.get("measure"):
        dim = g["dim"].lower().replace("breadth", "width")
        return MEASURES_CM.get((g["measure"].lower(), dim))
    if g.get("few"):
        return FEW_CM[g["few"].lower()]
    num = g["num"].lower()
    n = float(num) if num[0].isdigit() else _NUMBER_WORDS[num]
    if g.get("half") or g.get("half2"):
        n += 0.5
    return n * _unit_cm(g["unit"])


def plain_quantities(text: str) -> tuple[str, list[Plain]]:
    """``text`` with each distance said in words, other units or body measures said in
    centimetres ("5.1 cm"), and what was rewritten, in the text's order."""
    found: list[tuple[int, int, Plain]] = []
    for pattern in _PATTERNS:
        for m in pattern.finditer(text):
            if any(a < m.end() and m.start() < b for a, b, _ in found):
                continue
            cm = _value(m)
            if cm is None or cm <= 0:
                continue
            if m.groupdict().get("unit") and _unit_cm(m.group("unit")) == 1.0 \
                    and m.group("num")[0].isdigit() and not m.group("half"):
                continue  # already centimetres in digits
            found.append((m.start(), m.end(), Plain(m.group(0), round(cm + 1e-9, 1))))
    found.sort(key=lambda f: f[0])
    for start, end, p in reversed(found):
        text = f"{text[:start]}{p.cm:g} cm{text[end:]}"
    return text, [p for _, _, p in found]


def plain_instruction(instruction: str, transcript: Transcript) -> str:
    """``instruction`` with its distances said plainly (:func:`plain_quantities`), each
    rewrite recorded as a ``quantity_said_plainly`` transcript event."""
    text, done = plain_quantities(instruction)
    for p in done:
        transcript.write("quantity_said_plainly", instruction=instruction, **p.to_json())
    return text


__all__ = ["MEASURES_CM", "UNITS_CM", "Plain", "plain_instruction", "plain_quantities"]
