"""Which objects a reset puts on the table, and where (sampled from a Generator passed in).

A :class:`SceneLayout` says which blocks and lines must be present, how many random distractors
to add, whether the cabinet stands on the table, how far each drawer is open and (optionally) the
exact pose of some objects. :func:`sample_placement` turns it into a :class:`Placement`: a pose for
every present object, with no two objects overlapping and every block within the robot's reach.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Final

import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import DRAWERS
from voxposer.envs.config import COLORS, WorldConfig
from voxposer.errors import LayoutError
from voxposer.tabletop import CABINET_SIZE, DRAWER_TRAVEL

#: Region (x, y) [m] where random objects are placed: in front of the robot, clear of the edges.
PLACE_MIN: Final = (-0.36, -0.36)
PLACE_MAX: Final = (0.16, 0.36)
#: Blocks are kept within this horizontal distance [m] of the robot base (reachable top-down).
MAX_REACH: Final = 0.74
MIN_REACH: Final = 0.26
_ATTEMPTS: Final = 400


def _colour(name: str, kind: str) -> str:
    key = " ".join(str(name).lower().replace("_", " ").split())
    key = key.removesuffix(f" {kind}").replace("grey", "gray")
    if key not in COLORS:
        raise LayoutError(f"unknown {kind} {name!r}; colours are: {', '.join(COLORS)}")
    return key


def _range(name: str, value: tuple[int, int]) -> tuple[int, int]:
    lo, hi = (int(v) for v in value)
    if not 0 <= lo <= hi <= len(COLORS):
        raise LayoutError(f"SceneLayout.{name} must be 0 <= lo <= hi <= 10; got {value!r}")
    return lo, hi


@dataclass(frozen=True)
class SceneLayout:
    """What a reset must put in the scene.

    Attributes:
        blocks: colours (or names, "blue block") of blocks that must be present.
        lines: colours (or names, "blue line") of lines that must be present.
        extra_blocks: inclusive range of how many random distractor blocks to add.
        extra_lines: inclusive range of how many random distractor lines to add.
        cabinet: whether the cabinet stands on the table.
        drawer_openings: drawer ("top", "middle", "bottom" or "top drawer") → opening [m],
            0 (closed) to 0.2; drawers not named are closed.
        poses: object name → (x, y) or (x, y, yaw) [m, m, rad] for objects placed by hand.
        ee_start: where the end effector starts, top-down, position [m]; None: the rest pose.
        ee_start_yaw: … turned this much about the vertical [rad] (0: the fingers open along y;
            pi/2: along x).
    """

    blocks: tuple[str, ...] = ()
    lines: tuple[str, ...] = ()
    extra_blocks: tuple[int, int] = (3, 5)
    extra_lines: tuple[int, int] = (1, 3)
    cabinet: bool = True
    drawer_openings: Mapping[str, float] = field(default_factory=dict)
    poses: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    ee_start: tuple[float, float, float] | None = None
    ee_start_yaw: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "blocks", tuple(_colour(b, "block") for b in self.blocks))
        object.__setattr__(self, "lines", tuple(_colour(b, "line") for b in self.lines))
        object.__setattr__(self, "extra_blocks", _range("extra_blocks", self.extra_blocks))
        object.__setattr__(self, "extra_lines", _range("extra_lines", self.extra_lines))
        openings = {}
        for key, value in dict(self.drawer_openings).items():
            which = str(key).lower().removesuffix(" drawer").strip()
            if which not in DRAWERS:
                raise LayoutError(f"unknown drawer {key!r}; drawers are: {', '.join(DRAWERS)}")
            if not (math.isfinite(value) and 0.0 <= value <= DRAWER_TRAVEL):
                raise LayoutError(f"drawer opening of {key!r} must be in [0, 0.2] m; got {value!r}")
            openings[which] = float(value)
        object.__setattr__(self, "drawer_openings", openings)
        poses = {}
        for key, pose in dict(self.poses).items():
            parts = str(key).lower().split()
            kind = parts[-1] if parts else ""
            if kind not in ("block", "line"):
                raise LayoutError(f"poses key {key!r} must name a block or a line ('blue block')")
            colour = _colour(key, kind)
            p = tuple(float(v) for v in pose)
            if len(p) not in (2, 3) or not all(math.isfinite(v) for v in p):
                raise LayoutError(f"pose of {key!r} must be finite (x, y) or (x, y, yaw); got {pose!r}")
            poses[f"{colour} {kind}"] = p
        object.__setattr__(self, "poses", poses)


@dataclass(frozen=True)
class Placement:
    """Poses chosen by :func:`sample_placement`.

    Attributes:
        blocks: colour → (x, y, yaw) [m, m, rad] of every present block.
        lines: colour → (x, y, yaw) of every present line (a line lies along its local x).
        cabinet: whether the cabinet is present.
        drawer_openings: drawer → opening [m] (all three drawers).
    """

    blocks: dict[str, tuple[float, float, float]]
    lines: dict[str, tuple[float, float, float]]
    cabinet: bool
    drawer_openings: dict[str, float]


def _segment(pose: tuple[float, float, float], half_len: float) -> NDArray[np.float64]:
    x, y, yaw = pose
    d = np.array([math.cos(yaw), math.sin(yaw)]) * half_len
    t = np.linspace(-1.0, 1.0, 9)[:, None]
    return np.array([x, y]) + t * d


def _clearance(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    return float(np.min(np.linalg.norm(a[:, None, :] - b[None, :, :], axis=-1)))


class _Occupied:
    """Footprints already placed: point sets (x, y) with a radius [m]."""

    def __init__(self) -> None:
        self.items: list[tuple[NDArray[np.float64], float]] = []

    def free(self, pts: NDArray[np.float64], radius: float) -> bool:
        return all(_clearance(pts, q) >= radius + r for q, r in self.items)

    def add(self, pts: NDArray[np.float64], radius: float) -> None:
        self.items.append((pts, radius))


def sample_placement(layout: SceneLayout, rng: np.random.Generator, cfg: WorldConfig) -> Placement:
    """Choose which objects are present and their poses; no overlaps, blocks reachable.

    Raises:
        LayoutError: when a hand-placed pose overlaps another or no free spot can be found.
    """
    block_r = cfg.block_size * math.sqrt(2) / 2 + 0.01
    line_half = cfg.line_length / 2
    line_r = cfg.line_width / 2 + 0.01
    base = np.asarray(cfg.robot_base[:2])
    occ = _Occupied()
    if layout.cabinet:
        cx, cy = cfg.cabinet_position
        sx, sy = CABINET_SIZE[0] / 2, CABINET_SIZE[1] / 2
        xs, ys = np.linspace(cx - sx, cx + sx, 9), np.linspace(cy - sy - 0.05, cy + sy, 9)
        occ.add(np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2), 0.03)

    extra_b = [c for c in COLORS if c not in layout.blocks]
    extra_l = [c for c in COLORS if c not in layout.lines]
    n_b = int(rng.integers(layout.extra_blocks[0], layout.extra_blocks[1] + 1))
    n_l = int(rng.integers(layout.extra_lines[0], layout.extra_lines[1] + 1))
    blocks = list(layout.blocks) + [str(c) for c in rng.permutation(extra_b)[: max(0, n_b)]]
    lines = list(layout.lines) + [str(c) for c in rng.permutation(extra_l)[: max(0, n_l)]]
    for colour, kind in [(k.split()[0], k.split()[1]) for k in layout.poses]:
        target = blocks if kind == "block" else lines
        if colour not in target:
            target.append(colour)

    placed_b: dict[str, tuple[float, float, float]] = {}
    placed_l: dict[str, tuple[float, float, float]] = {}
    todo = [(c, "line") for c in lines] + [(c, "block") for c in blocks]
    todo.sort(key=lambda item: f"{item[0]} {item[1]}" not in layout.poses)  # hand-placed first
    for colour, kind in todo:
        key = f"{colour} {kind}"
        radius = line_r if kind == "line" else block_r
        for _ in range(_ATTEMPTS if key not in layout.poses else 1):
            if key in layout.poses:
                given = layout.poses[key]
                pose = (given[0], given[1], given[2] if len(given) == 3 else 0.0)
            else:
                xy = rng.uniform(PLACE_MIN, PLACE_MAX)
                yaw = float(rng.uniform(0.0, math.pi if kind == "line" else math.pi / 2))
                pose = (float(xy[0]), float(xy[1]), yaw)
                if kind == "block" and not MIN_REACH <= np.linalg.norm(xy - base) <= MAX_REACH:
                    continue
            pts = _segment(pose, line_half) if kind == "line" else np.array([pose[:2]])
            if occ.free(pts, radius):
                occ.add(pts, radius)
                (placed_l if kind == "line" else placed_b)[colour] = pose
                break
        else:
            raise LayoutError(f"no free spot for the {key} at {layout.poses.get(key, 'random')} "
                              f"(objects so far: {sorted(placed_b)} blocks, {sorted(placed_l)} lines)")
    openings = {d: float(layout.drawer_openings.get(d, 0.0)) for d in DRAWERS}
    return Placement(placed_b, placed_l, layout.cabinet, openings)
