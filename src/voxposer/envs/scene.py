"""The tabletop scene built in code with :class:`mujoco.MjSpec` (App. A.5).

Elements and their names (every body, geom, joint, camera and light is named):

* ``floor`` and a ``table`` (top surface at z = 0) with four legs;
* the Panda (``panda_*``, see :mod:`voxposer.envs.robot_model`) at the back of the table;
* ten blocks ``<colour>_block`` (free joint ``<colour>_block_joint``, geom ``<colour>_block_geom``);
* ten thin lines ``<colour>_line`` (mocap bodies, visual only: contype/conaffinity 0);
* a ``cabinet`` (mocap body) with drawers ``top_drawer``, ``middle_drawer``, ``bottom_drawer``
  (slide joints ``<which>_drawer_joint``, opening toward −y) each with a ``<which>_drawer_handle``;
* a hidden ``parking`` platform far below the floor where absent blocks wait;
* cameras ``<name>_camera`` from :class:`~voxposer.envs.config.CameraConfig`.
"""

from __future__ import annotations

from typing import Final

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.envs.config import COLORS, CameraConfig, WorldConfig
from voxposer.envs.robot_model import add_panda
from voxposer.tabletop import (
    CABINET_SIZE,
    CABINET_WALL,
    DRAWER_TRAVEL,
    HANDLE_HALF,
    HANDLE_STANDOFF,
    drawer_slots,
)

#: Environment collision bits (collide with everything, including the robot).
ENV_CONTYPE: Final = 1
ENV_CONAFFINITY: Final = 1
#: Height of the parking platform's top surface [m] (out of every camera's view, under the floor).
PARKING_Z: Final = -5.0
FLOOR_Z: Final = -0.75

#: Mass of one drawer [kg] (its size and travel: :mod:`voxposer.tabletop`).
DRAWER_MASS: Final = 0.6


def _box(body: mujoco.MjsBody, name: str, half: tuple[float, float, float],
         pos: tuple[float, float, float], rgba: tuple[float, float, float, float],
         *, collide: bool = True, mass: float | None = None) -> mujoco.MjsGeom:
    geom = body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_BOX, size=list(half),
                         pos=list(pos), rgba=list(rgba))
    geom.contype = ENV_CONTYPE if collide else 0
    geom.conaffinity = ENV_CONAFFINITY if collide else 0
    if mass is not None:
        geom.mass = mass
    return geom


def look_at_quat(pos: NDArray[np.float64], target: NDArray[np.float64]) -> NDArray[np.float64]:
    """MuJoCo camera quaternion (w, x, y, z) looking from ``pos`` to ``target`` with z up.

    A MuJoCo camera looks along its local −z with +y up in the image.
    """
    forward = target - pos
    forward = forward / np.linalg.norm(forward)
    right = np.cross(forward, np.array([0.0, 0.0, 1.0]))
    right = right / np.linalg.norm(right)
    up = np.cross(right, forward)
    mat = np.column_stack([right, up, -forward])
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, mat.reshape(-1))
    return quat


def _add_table(spec: mujoco.MjSpec, cfg: WorldConfig) -> None:
    world = spec.worldbody
    floor = world.add_body(name="floor")
    _box(floor, "floor_geom", (3.0, 3.0, 0.05), (0.0, 0.0, FLOOR_Z - 0.05), (0.35, 0.33, 0.30, 1))
    parking = world.add_body(name="parking")
    _box(parking, "parking_platform", (2.0, 2.0, 0.05), (0.0, 0.0, PARKING_Z - 0.05),
         (0.2, 0.2, 0.2, 1))
    table = world.add_body(name="table")
    lo, hi = np.asarray(cfg.table_min), np.asarray(cfg.table_max)
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    _box(table, "table_top", (half[0], half[1], 0.02), (centre[0], centre[1], -0.02),
         (0.78, 0.70, 0.58, 1))
    leg_h = (-FLOOR_Z - 0.04) / 2
    for k, (sx, sy) in enumerate(((-1, -1), (-1, 1), (1, -1), (1, 1))):
        pos = (centre[0] + sx * (half[0] - 0.05), centre[1] + sy * (half[1] - 0.05), -0.04 - leg_h)
        _box(table, f"table_leg_{k}", (0.025, 0.025, leg_h), pos, (0.45, 0.40, 0.33, 1))


def _add_blocks(spec: mujoco.MjSpec, cfg: WorldConfig) -> None:
    half = cfg.block_size / 2
    for k, (colour, rgba) in enumerate(COLORS.items()):
        body = spec.worldbody.add_body(name=f"{colour}_block",
                                       pos=[0.12 * k - 0.6, 0.0, PARKING_Z + half])
        body.add_freejoint(name=f"{colour}_block_joint")
        geom = _box(body, f"{colour}_block_geom", (half, half, half), (0, 0, 0), rgba,
                    mass=cfg.block_mass)
        geom.friction = [cfg.block_friction, 0.005, 0.0001]
        geom.condim = 4


def _add_lines(spec: mujoco.MjSpec, cfg: WorldConfig) -> None:
    for k, (colour, rgba) in enumerate(COLORS.items()):
        body = spec.worldbody.add_body(name=f"{colour}_line", mocap=True,
                                       pos=[0.0, 0.05 * k, PARKING_Z - 1.0])
        _box(body, f"{colour}_line_geom", (cfg.line_length / 2, cfg.line_width / 2, 0.001),
             (0, 0, 0.001), rgba, collide=False)


def _add_cabinet(spec: mujoco.MjSpec, cfg: WorldConfig) -> None:
    sx, sy, sz = (s / 2 for s in CABINET_SIZE)
    w = CABINET_WALL / 2
    wood = (0.55, 0.36, 0.22, 1.0)
    cab = spec.worldbody.add_body(name="cabinet", mocap=True,
                                  pos=[cfg.cabinet_position[0], cfg.cabinet_position[1], 0.0])
    _box(cab, "cabinet_top", (sx, sy, w), (0, 0, 2 * sz - w), wood)
    _box(cab, "cabinet_bottom", (sx, sy, w), (0, 0, w), wood)
    _box(cab, "cabinet_left_wall", (w, sy, sz), (-sx + w, 0, sz), wood)
    _box(cab, "cabinet_right_wall", (w, sy, sz), (sx - w, 0, sz), wood)
    _box(cab, "cabinet_back", (sx, w, sz), (0, sy - w, sz), wood)
    inner_x = sx - CABINET_WALL - 0.004
    front = (0.85, 0.80, 0.72, 1.0)
    for k, drawer in enumerate(drawer_slots()):
        which, slot = drawer.name, 2 * (drawer.half_height + 0.006)
        if k > 0:  # the shelf above this drawer
            _box(cab, f"cabinet_shelf_{k}", (sx - CABINET_WALL, sy - CABINET_WALL, w / 2),
                 (0, 0, drawer.centre_z + slot / 2), wood)
        body = cab.add_body(name=f"{which}_drawer", pos=[0.0, 0.0, drawer.centre_z])
        joint = body.add_joint(name=f"{which}_drawer_joint", type=mujoco.mjtJoint.mjJNT_SLIDE,
                               axis=[0.0, -1.0, 0.0], range=[0.0, DRAWER_TRAVEL])
        joint.damping = [8.0, 0.0, 0.0]
        joint.frictionloss = 0.5
        joint.armature = 0.05
        hz = drawer.half_height
        depth = sy - CABINET_WALL - 0.003
        m = DRAWER_MASS / 5
        _box(body, f"{which}_drawer_front", (sx - 0.003, w, hz + 0.003), (0, -sy + w, 0), front,
             mass=m)
        _box(body, f"{which}_drawer_bottom", (inner_x, depth - w, w / 2),
             (0, -CABINET_WALL / 2, -hz + w / 2), front, mass=m)
        _box(body, f"{which}_drawer_left", (w / 2, depth - w, hz * 0.7),
             (-inner_x + w / 2, -CABINET_WALL / 2, -hz * 0.3), front, mass=m)
        _box(body, f"{which}_drawer_right", (w / 2, depth - w, hz * 0.7),
             (inner_x - w / 2, -CABINET_WALL / 2, -hz * 0.3), front, mass=m)
        _box(body, f"{which}_drawer_rear", (inner_x, w / 2, hz * 0.7),
             (0, depth - CABINET_WALL, -hz * 0.3), front, mass=m)
        handle = body.add_body(name=f"{which}_drawer_handle", pos=[0.0, -sy - HANDLE_STANDOFF, 0.0])
        metal = (0.25, 0.25, 0.28, 1.0)
        _box(handle, f"{which}_drawer_handle_bar", HANDLE_HALF, (0, 0, 0), metal, mass=0.05)
        for j, x in enumerate((-0.055, 0.055)):
            _box(handle, f"{which}_drawer_handle_post_{j}", (0.006, 0.012, 0.006),
                 (x, 0.019, 0), metal, mass=0.01)


def _add_cameras_and_lights(spec: mujoco.MjSpec, cams: CameraConfig) -> None:
    world = spec.worldbody
    target = np.asarray(cams.target, dtype=np.float64)
    for name, pos in cams.positions:
        p = np.asarray(pos, dtype=np.float64)
        world.add_camera(name=f"{name}_camera", pos=p.tolist(),
                         quat=look_at_quat(p, target).tolist(), fovy=cams.fovy)
    for k, pos in enumerate(((0.0, -1.0, 2.5), (0.0, 1.0, 2.5), (-1.5, 0.0, 2.0))):
        light = world.add_light(name=f"light_{k}", pos=list(pos),
                                dir=(-np.asarray(pos) / np.linalg.norm(pos)).tolist())
        light.diffuse = [0.28, 0.28, 0.28]
        light.specular = [0.1, 0.1, 0.1]
        light.castshadow = cams.shadows and k == 0


def build_scene_spec(cfg: WorldConfig) -> mujoco.MjSpec:
    """The full tabletop scene as an uncompiled spec (see the module docstring for its names)."""
    spec = mujoco.MjSpec()
    spec.modelname = "voxposer_tabletop"
    opt = spec.option
    opt.timestep = cfg.timestep
    opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    opt.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    opt.impratio = 10.0
    spec.visual.headlight.ambient = [0.25, 0.25, 0.25]
    spec.visual.headlight.diffuse = [0.3, 0.3, 0.3]
    spec.visual.quality.offsamples = 4 if cfg.cameras.antialias else 0
    spec.visual.quality.shadowsize = 2048 if cfg.cameras.shadows else 0
    spec.visual.global_.offwidth = max(640, cfg.cameras.width)
    spec.visual.global_.offheight = max(480, cfg.cameras.height)
    spec.visual.map.znear = 0.01
    spec.stat.extent = 2.0
    spec.stat.center = [-0.2, 0.0, 0.2]
    _add_table(spec, cfg)
    add_panda(spec, cfg.robot_base)
    _add_blocks(spec, cfg)
    _add_lines(spec, cfg)
    _add_cabinet(spec, cfg)
    _add_cameras_and_lights(spec, cfg.cameras)
    return spec


def build_scene(cfg: WorldConfig) -> mujoco.MjModel:
    """The compiled tabletop scene."""
    return build_scene_spec(cfg).compile()
