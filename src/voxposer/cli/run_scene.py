"""The scene ``voxposer run`` sets up for an instruction, and the ``--drawer-open`` / ``--place``
options that override it.

Every block and line the instruction names is placed (at random, clear of the others); a drawer
it asks to close ("close the bottommost drawer", "push the top drawer closed", "shut whichever
drawer is open": one drawer drawn from the run's generator) starts open ``CLOSE_OPENING_M``; a
drawer it asks to open starts closed. ``--drawer-open`` replaces the automatic drawer choice,
``--place`` puts a block or line at a given (x, y) on the table [m]. :meth:`SceneChoice.describe`
is the ``scene`` field of ``summary.json``: what was set, where, and why.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final

import numpy as np

from voxposer import tabletop
from voxposer.catalog import COLOR_NAMES, DRAWERS
from voxposer.cli.scene_cabinet import cabinet_choice
from voxposer.errors import ConfigError

if TYPE_CHECKING:
    from voxposer.envs.layout import Placement, SceneLayout

#: How far [m] a drawer the instruction asks to close (or ``--drawer-open`` names) is open.
CLOSE_OPENING_M: Final = 0.15
NAMED: Final = "named in the instruction"
PLACED: Final = "--place"
DISTRACTOR: Final = "distractor"
ASKED_CLOSE: Final = "asked to close it"
ASKED_CLOSE_ANY: Final = "asked to close a drawer without naming one: chosen at random"
ASKED_OPEN: Final = "asked to open it"
OPTION: Final = "--drawer-open"
CLOSED: Final = "closed (not asked about)"
NOT_OPTION: Final = "closed (not in --drawer-open)"
#: Words for the three drawers ("the bottommost drawer", "the drawer in the middle").
DRAWER_WORDS: Final = {
    **dict.fromkeys(("top", "topmost", "upper", "uppermost", "highest", "first"), "top"),
    **dict.fromkeys(("middle", "center", "centre", "central", "second"), "middle"),
    **dict.fromkeys(("bottom", "bottommost", "lower", "lowermost", "lowest", "third", "last"),
                    "bottom"),
}
#: ``drawer_requests`` keys for a drawer not named ("whichever drawer") and for every drawer.
ONE: Final = "one"
ALL: Final = "all"
_NAME = "|".join(sorted(DRAWER_WORDS, key=len, reverse=True))
_MENTION = re.compile(
    rf"\b(?P<names>(?:{_NAME})(?:\s*(?:,|and|or|&)\s*(?:the\s+)?(?:{_NAME}))*)\s+drawers?\b"
    rf"|\bdrawers?\s+(?:at|on|in)\s+the\s+(?P<after>{_NAME})\b"
    r"|(?P<all>\b(?:all|every|each)(?:\s+(?:of|the|three))*\s+drawers?\b"
    r"|(?<!\bof )\bthe\s+drawers\b)"
    r"|\bdrawer(?P<plural>s)?\b|\b(?P<it>it|them)\b")
_VERB = re.compile(
    r"(?P<close>\b(?:close|closes|closing|shut|shuts|shutting|push|pushes|pushing|shove|shoves)\b"
    r"(?!\s+(?:to|by)\b))|(?P<open>\b(?:open|opens|opening|pull|pulls|pulling)\b)"
    r"|(?P<other>\b(?:move|put|place|pick|grab|grasp|take|go|reach|touch|stack|sweep|drop|lift"
    r"|hold|bring|carry|avoid|leave|rotate|turn|blocks?|lines?|gripper|table)\b|[.;!?])")
_AFTER_CLOSE = re.compile(r"\s+(?:(?:is|are|all the way|back|fully|completely)\s+)*(?:closed|shut)"
                          r"\b|\s+(?:all the way\s+|back\s+)?in\s*(?:$|[.,;!?]|and\b|then\b)")
_AFTER_OPEN = re.compile(r"\s+(?:all the way\s+|fully\s+|wide\s+)?(?:open|out)\b")
#: A word before "open" that makes it a state ("is open", "the open drawer"), not a request.
_STATE_WORDS: Final = frozenset({"is", "are", "was", "were", "be", "been", "stays", "remains",
                                 "left", "still", "wide", "half", "partly", "already", "the",
                                 "an", "one", "any", "whichever"})


def _mentioned(match: re.Match[str]) -> tuple[str, ...]:
    """The drawers (or ``ONE`` / ``ALL``) a mention of ``_MENTION`` names."""
    if match.group("names"):
        return tuple(DRAWER_WORDS[w] for w in re.findall(rf"\b(?:{_NAME})\b", match["names"]))
    if match.group("after"):
        return (DRAWER_WORDS[match["after"]],)
    if match.group("all"):
        return (ALL,)
    if match.group("plural") and not match.string[:match.start()].endswith("of the "):
        return (ALL,)
    return (ONE,)


def drawer_requests(instruction: str) -> dict[str, str]:
    """What ``instruction`` asks of each drawer: drawer / ``ONE`` / ``ALL`` → "close" or
    "open" (the first request about a drawer counts). A mention takes the request of the verb
    before it in its sentence ("close", "shut", "push" / "open", "pull") unless words after it
    say ("push the top drawer closed", "pull the top drawer out")."""
    text = re.sub(r"(?<=\w)-most\b", "most", instruction.lower())
    events = sorted([*((m.start(), 0, m) for m in _VERB.finditer(text)),
                     *((m.start(), 1, m) for m in _MENTION.finditer(text))],
                    key=lambda e: (e[0], e[1]))
    verb: str | None = None
    last: tuple[str, ...] = ()  # what "it" refers to
    asks: dict[str, str] = {}
    for _, is_mention, match in events:
        if not is_mention:
            before = text[:match.start()].split()
            if match.lastgroup == "open" and before and before[-1] in _STATE_WORDS:
                continue
            verb = None if match.lastgroup == "other" else match.lastgroup
            last = () if match.lastgroup == "other" and match[0].isalpha() else last
            continue
        named = last if match.group("it") else _mentioned(match)
        last = named
        action = ("close" if _AFTER_CLOSE.match(text, match.end())
                  else "open" if _AFTER_OPEN.match(text, match.end()) else verb)
        if action is not None:
            for which in named:
                asks.setdefault(which, action)
    return asks


def _half_extent(kind: str) -> tuple[float, float]:
    """Half size (x, y) [m] of a block, or of a line lying along x (yaw 0)."""
    if kind == "line":
        return tabletop.LINE_LENGTH / 2, tabletop.LINE_WIDTH / 2
    return tabletop.BLOCK_SIZE / 2, tabletop.BLOCK_SIZE / 2


def allowed_range(kind: str) -> tuple[tuple[float, float], tuple[float, float]]:
    """The (x, y) range [m] a ``--place``d block's or line's centre may take: its footprint
    stays on the table top."""
    hx, hy = _half_extent(kind)
    lo, hi = tabletop.TABLE_MIN, tabletop.TABLE_MAX
    return (lo[0] + hx, hi[0] - hx), (lo[1] + hy, hi[1] - hy)


def parse_place(text: str) -> tuple[str, tuple[float, float]]:
    """``"blue block=0.05,-0.1"`` → ``("blue block", (0.05, -0.1))``; metres, on the table.

    Raises:
        ConfigError: naming the bad part, the known colours or the allowed range.
    """
    name, sep, where = str(text).partition("=")
    words = name.lower().replace("grey", "gray").split()
    if not sep or len(words) != 2 or words[1] not in ("block", "line"):
        raise ConfigError(f"--place {text!r} must read '<colour> block=<x>,<y>' or "
                          "'<colour> line=<x>,<y>' (metres), e.g. 'blue block=0.0,-0.2'")
    colour, kind = words
    if colour not in COLOR_NAMES:
        raise ConfigError(f"--place {text!r}: unknown colour {colour!r}; colours are: "
                          f"{', '.join(COLOR_NAMES)}")
    try:
        xy = tuple(float(v) for v in where.split(","))
    except ValueError:
        xy = ()
    if len(xy) != 2 or not all(math.isfinite(v) for v in xy):
        raise ConfigError(f"--place {text!r}: the position must be two finite numbers "
                          f"'<x>,<y>' in metres; got {where!r}")
    for axis, (v, (lo, hi)) in enumerate(zip(xy, allowed_range(kind), strict=True)):
        if not lo <= v <= hi:
            (xlo, xhi), (ylo, yhi) = allowed_range(kind)
            raise ConfigError(
                f"--place {text!r}: {'xy'[axis]} = {v} m is off the table; a {kind}'s centre "
                f"must lie in x ∈ [{xlo:.3f}, {xhi:.3f}] m, y ∈ [{ylo:.3f}, {yhi:.3f}] m "
                "(front +x, left −y)")
    return f"{colour} {kind}", (xy[0], xy[1])


def parse_drawer_open(text: str) -> tuple[str, float]:
    """``"top"`` → ``("top", CLOSE_OPENING_M)``; ``"top=0.1"`` → ``("top", 0.1)`` [m].

    Raises:
        ConfigError: an unknown drawer (the message lists them) or an opening outside
            [0, DRAWER_TRAVEL] m (:mod:`voxposer.tabletop`).
    """
    which, sep, amount = str(text).lower().partition("=")
    which = which.strip().removesuffix(" drawer").strip()
    if which not in DRAWERS:
        raise ConfigError(f"--drawer-open {text!r}: unknown drawer {which!r}; drawers are: "
                          f"{', '.join(DRAWERS)} (optionally '=<opening in m>')")
    try:
        opening = float(amount) if sep else CLOSE_OPENING_M
    except ValueError:
        opening = math.nan
    if not (math.isfinite(opening) and 0.0 <= opening <= tabletop.DRAWER_TRAVEL):
        raise ConfigError(f"--drawer-open {text!r}: the opening must be in "
                          f"[0, {tabletop.DRAWER_TRAVEL}] m; got {amount!r}")
    return which, opening


@dataclass(frozen=True)
class SceneRequest:
    """What the scene options asked for.

    Attributes:
        drawer_open: drawer → opening [m] from ``--drawer-open`` (empty: choose automatically).
        places: "blue block" / "blue line" → (x, y) [m] from ``--place``.
    """

    drawer_open: dict[str, float] = field(default_factory=dict)
    places: dict[str, tuple[float, float]] = field(default_factory=dict)

    @classmethod
    def from_options(cls, drawer_open: Sequence[str] = (), places: Sequence[str] = ()
                     ) -> SceneRequest:
        """Validate the raw option values; raises ConfigError (naming the value) on the first
        bad one, or when one object is placed twice."""
        opened = dict(parse_drawer_open(d) for d in drawer_open)
        placed: dict[str, tuple[float, float]] = {}
        for text in places:
            name, xy = parse_place(text)
            if name in placed:
                raise ConfigError(f"--place gives the {name} twice: {placed[name]} and {xy}")
            placed[name] = xy
        return cls(opened, placed)


def named_objects(instruction: str, kind: str) -> tuple[str, ...]:
    """Colours of the ``kind``s ("block", "line") the instruction names, in colour order
    ("the blue block", "the red and green blocks")."""
    text = instruction.lower().replace("grey", "gray")
    colours = "|".join(COLOR_NAMES)
    found: set[str] = set()
    pattern = rf"\b((?:{colours})(?:\s*(?:,|and|or|&)\s*(?:the\s+)?(?:{colours}))*)\s+{kind}s?\b"
    for match in re.finditer(pattern, text):
        found.update(re.findall(rf"\b(?:{colours})\b", match.group(1)))
    return tuple(c for c in COLOR_NAMES if c in found)


@dataclass(frozen=True)
class SceneChoice:
    """The layout of a run and why each object and drawer is set as it is.

    Attributes:
        layout: what the reset puts in the scene.
        why: "blue block" / "top drawer" → the reason it was set (``NAMED``, ``PLACED``,
            ``ASKED_CLOSE``, ``ASKED_CLOSE_ANY``, ``ASKED_OPEN``, ``OPTION``).
    """

    layout: SceneLayout
    why: dict[str, str]

    def describe(self, placement: Placement | None = None) -> dict[str, Any]:
        """The ``scene`` field of ``summary.json``: every block and line with its ``why`` and,
        once ``placement`` is known, ``xy_m`` [m] and ``yaw_rad`` (before: the ``--place``d
        position or None); every drawer's ``opening_m`` [m] and ``why``; the cabinet."""
        def objects(kind: str) -> list[dict[str, Any]]:
            placed = getattr(placement, f"{kind}s") if placement is not None else {}
            names = dict.fromkeys([*(f"{c} {kind}" for c in getattr(self.layout, f"{kind}s")),
                                   *(n for n in self.layout.poses if n.endswith(kind)),
                                   *(f"{c} {kind}" for c in placed)])
            rows = []
            for name in names:
                pose = placed.get(name.split()[0]) or self.layout.poses.get(name) or ()
                rows.append({
                    "name": name, "why": self.why.get(name, DISTRACTOR),
                    "xy_m": [round(float(v), 4) for v in pose[:2]] if pose else None,
                    "yaw_rad": round(float(pose[2]), 4) if len(pose) > 2 else None})
            return rows

        openings = placement.drawer_openings if placement else self.layout.drawer_openings
        return {
            "blocks": objects("block"),
            "lines": objects("line"),
            "cabinet": self.layout.cabinet,
            "cabinet_why": self.why.get("cabinet", ""),
            "drawers": [{"drawer": d, "opening_m": round(float(openings.get(d, 0.0)), 4),
                         "why": self.why.get(f"{d} drawer", CLOSED)} for d in DRAWERS],
        }


def _drawers(instruction: str, rng: np.random.Generator, request: SceneRequest
             ) -> tuple[dict[str, float], dict[str, str]]:
    """Drawer openings [m] and reasons: ``--drawer-open``, else what the instruction asks."""
    if request.drawer_open:
        return dict(request.drawer_open), {
            f"{d} drawer": OPTION if d in request.drawer_open else NOT_OPTION for d in DRAWERS}
    asks = drawer_requests(instruction)
    openings: dict[str, float] = {}
    why: dict[str, str] = {}
    for which, action in asks.items():
        if which in DRAWERS:
            openings[which] = CLOSE_OPENING_M if action == "close" else 0.0
            why[f"{which} drawer"] = ASKED_CLOSE if action == "close" else ASKED_OPEN
    if asks.get(ALL) == "close":
        for which in DRAWERS:
            if which not in why:
                openings[which], why[f"{which} drawer"] = CLOSE_OPENING_M, ASKED_CLOSE
    elif asks.get(ONE) == "close" and not any(v == ASKED_CLOSE for v in why.values()):
        free = [d for d in DRAWERS if d not in why]
        if free:
            which = free[int(rng.integers(len(free)))]
            openings[which], why[f"{which} drawer"] = CLOSE_OPENING_M, ASKED_CLOSE_ANY
    return openings, why


def choose_scene(instruction: str, rng: np.random.Generator,
                 request: SceneRequest | None = None) -> SceneChoice:
    """The scene for ``instruction``: named blocks and lines plus distractors, drawers as the
    instruction asks, overridden by ``request``. Draws from ``rng`` only when a drawer must be
    picked at random."""
    from voxposer.envs.layout import SceneLayout

    request = request or SceneRequest()
    blocks, lines = named_objects(instruction, "block"), named_objects(instruction, "line")
    why = {f"{c} block": NAMED for c in blocks} | {f"{c} line": NAMED for c in lines}
    for name in request.places:
        why[name] = f"{NAMED}; {PLACED}" if name in why else PLACED
    openings, drawer_why = _drawers(instruction, rng, request)
    cabinet, why["cabinet"] = cabinet_choice(instruction)
    if openings and not cabinet:  # a drawer asked for by an option keeps its cabinet
        cabinet, why["cabinet"] = True, OPTION
    layout = SceneLayout(blocks=blocks, lines=lines, extra_blocks=(3, 5), extra_lines=(2, 3),
                         drawer_openings=openings, poses=dict(request.places), cabinet=cabinet)
    return SceneChoice(layout, why | drawer_why)
