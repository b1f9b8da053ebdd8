"""The voxel-index rule: value maps are indexed inside their grid; small arrays keep Python's
rules (negative indices count from the end)."""

from __future__ import annotations

import numpy as np
import pytest

from voxposer.errors import SandboxError, VoxelIndexError
from voxposer.lmp import make_tabletop_scene
from voxposer.lmp.api import LMPAPI
from voxposer.lmp.sandbox import Sandbox

SETUP = ("m = np.zeros((100, 100, 100))\nr = np.zeros((100, 100, 100, 4))\n"
         "x, y, z = 10, 20, 5\n")


@pytest.fixture(scope="module")
def sandbox() -> Sandbox:
    return Sandbox()


OFF_THE_GRID = {
    "m[-1, 0, 0] = 1": ("-1", 0),
    "v = m[0, 0, -15]": ("-15", 2),
    "m[x, y, z - 20] = 1": ("-15", 2),
    "m[x, y, np.int64(z) - 6] = 1": ("-1", 2),
    "m[100, 0, 0] = 1": ("100", 0),
    "v = m[0, 250, 0]": ("250", 1),
    "m[:, :, -5:] = 1": ("-5", 2),
    "v = m[x - 20:x, :, :]": ("-10", 0),
    "v = m[..., -1]": ("-1", 2),
    "m[np.array([1, -2]), 0, 0] = 1": ("-2", 0),
    "m[[1, -2], 0, 0] = 1": ("-2", 0),
    "m[0, np.array([5, 100]), 0] = 1": ("100", 1),
    "r[-1, 0, 0] = np.array([0, 0, 0, 1])": ("-1", 0),
    "v = r[0, -3]": ("-3", 1),
}


@pytest.mark.parametrize("code, expected", list(OFF_THE_GRID.items()))
def test_negative_or_too_large_voxel_indices_are_refused(sandbox: Sandbox, code: str,
                                                         expected: tuple[str, int]) -> None:
    index, axis = expected
    with pytest.raises(VoxelIndexError) as info:
        sandbox.run(SETUP + code, {})
    message = str(info.value)
    assert index in message and f"axis {axis}" in message
    assert "(100, 100, 100" in message  # the array's shape
    assert isinstance(info.value, SandboxError) and isinstance(info.value, IndexError)


def test_nothing_is_written_when_an_index_is_refused(sandbox: Sandbox) -> None:
    namespace = {"m": np.zeros((100, 100, 100))}
    with pytest.raises(VoxelIndexError):
        sandbox.run("m[0, 0, -15] = 1", namespace)
    assert not namespace["m"].any()  # numpy would have set m[0, 0, 85]


def test_a_target_below_the_table_is_refused_not_wrapped_to_the_top(sandbox: Sandbox) -> None:
    api = LMPAPI(make_tabletop_scene())
    code = ("affordance_map = get_empty_affordance_map()\n"
            "table = detect('table')\n"
            "x, y, z = table.position\n"
            "affordance_map[x, y, z - cm2index(15, 'z')] = 1\n"
            "ret_val = affordance_map\n")
    with pytest.raises(VoxelIndexError, match=r"voxel index -\d+ on axis 2 .*wrap.*np\.clip"):
        sandbox.run(code, api.namespace())


def test_ordinary_indexing_keeps_working(sandbox: Sandbox) -> None:
    code = SETUP + (
        "m[0, 0, 99] = 1\n"
        "m[x, y, z] = 2\n"
        "m[x - 5:x + 5, y, z:z + 200] = 3\n"  # a stop past the end is clipped, as usual
        "flipped = m[::-1]\n"
        "m[m > 2] = 4\n"
        "m[:] = m\n"
        "m[:, :, :] = m\n"
        "idx = np.argwhere(m == 4)\n"
        "m[tuple(idx.T)] = 5\n"
        "r[1, 2, 3, -1] = 1\n"  # a quaternion component: not a voxel axis
        "w = r[..., -1]\n"
        "p = np.array([1, 2, 3])\n"
        "last, head = p[-1], p[:-1]\n"
        "box = np.zeros((2, 3))\n"
        "top, zs = box[-1], box[:, -1]\n"
        "tail = [1, 2, 3][-1]\n"
    )
    out = sandbox.run(code, {})
    assert out["m"][0, 0, 99] == 1 and out["m"][10, 20, 5] == 5
    assert out["last"] == 3 and out["head"].tolist() == [1, 2] and out["tail"] == 3
    assert out["w"].shape == (100, 100, 100) and out["w"][1, 2, 3] == 1


def test_too_many_indices_stay_numpys_index_error(sandbox: Sandbox) -> None:
    """The self-correction recording relies on the model seeing this IndexError."""
    with pytest.raises(IndexError, match="too many indices") as info:
        sandbox.run(SETUP + "v = m[0, 0, 0, 0]", {})
    assert not isinstance(info.value, SandboxError)
