"""The programs' box test scene and the simulator are built from one layout description: the
cabinet, its drawer handles and the table are where the simulator's cameras see them."""

import numpy as np
import pytest

from tests.perceive import perceive
from voxposer.envs import SceneLayout, TabletopWorld
from voxposer.lmp.scene import make_tabletop_scene


@pytest.mark.parametrize("name", ["cabinet", "top drawer handle", "middle drawer handle",
                                  "bottom drawer handle"])
def test_the_box_scene_puts_the_cabinet_where_the_simulator_does(world: TabletopWorld,
                                                                 name: str) -> None:
    world.reset(np.random.default_rng(0), SceneLayout(blocks=("blue",), extra_blocks=(0, 0)))
    seen = perceive(world).detect(name).position
    boxed = make_tabletop_scene().detect(name).position
    assert np.linalg.norm(seen - boxed) < 0.03, (name, seen, boxed)


def test_no_block_of_the_box_scene_overlaps_the_cabinet() -> None:
    scene = make_tabletop_scene()
    cab = scene.box("cabinet")
    handles = [scene.box(f"{w} drawer handle") for w in ("top", "middle", "bottom")]
    for name in scene.object_names:
        if name.endswith(" block"):
            b = scene.box(name)
            for other in (cab, *handles):
                assert np.any(b.hi <= other.lo) or np.any(b.lo >= other.hi), name
