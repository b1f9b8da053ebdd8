"""A drawer's sliding axis from its normals: the front, told from the side walls by its handle."""

from types import SimpleNamespace

import numpy as np
import pytest

from voxposer.errors import ObjectNotVisibleError
from voxposer.perception.sliding_axis import dominant_normal, drawer_front_normal


def _open_drawer_normals(rng: np.random.Generator) -> np.ndarray:
    """An open drawer as noisy cameras see it: 600 side-wall normals facing +x within 5°, and
    400 front normals facing -y spread by 12° (depth noise on a face seen head-on)."""
    side = np.radians(rng.normal(0.0, 3.0, 600))
    front = np.radians(rng.normal(-90.0, 12.0, 400))
    angles = np.concatenate([side, front])
    return np.stack([np.cos(angles), np.sin(angles), rng.normal(0, 0.05, len(angles))], axis=1)


def test_the_side_walls_win_alone_and_the_handle_side_picks_the_front() -> None:
    normals = _open_drawer_normals(np.random.default_rng(0))
    np.testing.assert_allclose(dominant_normal(normals), [1, 0, 0], atol=0.05)
    front = dominant_normal(normals, toward=np.array([0.0, -1.0, 0.0]))
    np.testing.assert_allclose(front, [0, -1, 0], atol=0.1)


def _handle_points(rng: np.random.Generator, at: np.ndarray, bar: bool) -> np.ndarray:
    """200 handle points at ``at``: a 14 cm bar along x (1 cm noise across), or a 3 cm knob."""
    half = np.array([0.07, 0.01, 0.01]) if bar else np.array([0.015, 0.015, 0.015])
    return at + rng.uniform(-1.0, 1.0, (200, 3)) * half


def _detect(handle_at: tuple[float, float, float] | None, bar: bool = True):
    rng = np.random.default_rng(1)
    normals = _open_drawer_normals(rng)

    def detect(name: str) -> SimpleNamespace:
        if name == "top drawer":
            return SimpleNamespace(position=np.array([-0.05, 0.15, 0.29]), normals=normals)
        if handle_at is None:
            raise ObjectNotVisibleError(f"the {name} is in the scene but no camera sees it")
        at = np.array(handle_at)
        return SimpleNamespace(position=at, points=_handle_points(rng, at, bar),
                               normals=normals[:0])

    return detect


@pytest.mark.parametrize("bar", [True, False])
@pytest.mark.parametrize("handle", [(-0.05, 0.02, 0.29), (-0.052, 0.135, 0.28)])
def test_the_front_faces_the_handle(handle: tuple[float, float, float], bar: bool) -> None:
    """Square to a bar handle; a knob's side of the drawer picks the front's normals."""
    axis = drawer_front_normal(_detect(handle, bar), "top drawer")
    assert axis is not None and axis @ np.array([0.0, -1.0, 0.0]) > 0.99


def test_without_a_visible_handle_the_dominant_normal_is_taken() -> None:
    axis = drawer_front_normal(_detect(None), "top drawer")
    assert axis is not None and axis @ np.array([1.0, 0.0, 0.0]) > 0.99
