import pytest

from voxposer.envs import TabletopWorld


@pytest.fixture(scope="module")
def world() -> TabletopWorld:
    return TabletopWorld()
