"""Building blocks of the articulated scenes' MjSpec: geoms, hidden sites, the table, cameras.

The table, floor, cameras and lights follow the tabletop's conventions
(:mod:`voxposer.envs.scene`): the table top is z = 0, cameras are named ``<name>_camera`` and
aim at :attr:`CameraConfig.target`. Angles in every spec built here are radians.
"""

from __future__ import annotations

from typing import Final, Literal

import mujoco
import numpy as np

from voxposer.envs.config import CameraConfig
from voxposer.envs.robot_model import HIDDEN_SITE_GROUP
from voxposer.envs.scene import ENV_CONAFFINITY, ENV_CONTYPE, FLOOR_Z, look_at_quat

Vec3 = tuple[float, float, float]
RGBA = tuple[float, float, float, float]
GeomKind = Literal["box", "cylinder", "capsule"]

_TYPES: Final = {
    "box": mujoco.mjtGeom.mjGEOM_BOX,
    "cylinder": mujoco.mjtGeom.mjGEOM_CYLINDER,
    "capsule": mujoco.mjtGeom.mjGEOM_CAPSULE,
}
#: Colours shared by the scenes.
WOOD: Final[RGBA] = (0.55, 0.36, 0.22, 1.0)
PAINT: Final[RGBA] = (0.88, 0.86, 0.80, 1.0)
METAL: Final[RGBA] = (0.72, 0.72, 0.75, 1.0)
DARK_METAL: Final[RGBA] = (0.25, 0.25, 0.28, 1.0)
GLASS: Final[RGBA] = (0.70, 0.85, 0.95, 0.35)


def add_geom(body: mujoco.MjsBody, name: str, kind: GeomKind, size: tuple[float, ...],
             pos: Vec3 = (0.0, 0.0, 0.0), rgba: RGBA = PAINT, *,
             fromto: tuple[float, float, float, float, float, float] | None = None,
             collide: bool = True, mass: float | None = None,
             friction: float | None = None) -> mujoco.MjsGeom:
    """Add a named geom to ``body``.

    Args:
        body: the body it belongs to.
        name: unique geom name.
        kind: "box" (``size`` = half-extents [m], shape (3,)), "cylinder" or "capsule"
            (``size`` = (radius, half-length) [m], along local z; or radius only with ``fromto``).
        pos: centre in the body frame [m], shape (3,) (ignored with ``fromto``).
        rgba: colour.
        fromto: end points (x0, y0, z0, x1, y1, z1) [m] of a cylinder or capsule.
        collide: False for a visual-only geom (contype/conaffinity 0).
        mass: mass [kg]; None uses MuJoCo's default density.
        friction: sliding friction coefficient; None keeps MuJoCo's default (1).
    """
    geom = body.add_geom(name=name, type=_TYPES[kind], size=[*size, 0.0, 0.0][:3],
                         pos=list(pos), rgba=list(rgba))
    if fromto is not None:
        geom.fromto = list(fromto)
    geom.contype = ENV_CONTYPE if collide else 0
    geom.conaffinity = ENV_CONAFFINITY if collide else 0
    if mass is not None:
        geom.mass = mass
    if friction is not None:
        geom.friction = [friction, 0.005, 0.0001]
    return geom


def add_part_site(body: mujoco.MjsBody, pos: Vec3 = (0.0, 0.0, 0.0)) -> mujoco.MjsSite:
    """The site ``<body>_site`` marking a part's reference point [m] (hidden from cameras)."""
    site = body.add_site(name=f"{body.name}_site", pos=list(pos), size=[0.01, 0.01, 0.01])
    site.group = HIDDEN_SITE_GROUP
    return site


def new_spec(name: str, timestep: float, cams: CameraConfig) -> mujoco.MjSpec:
    """An empty spec with the tabletop's physics and rendering options, angles in radians.

    Args:
        name: the model name.
        timestep: physics step [s].
        cams: the cameras (their image size sizes the offscreen buffer).
    """
    spec = mujoco.MjSpec()
    spec.modelname = name
    spec.compiler.degree = False
    opt = spec.option
    opt.timestep = timestep
    opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    opt.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    opt.impratio = 10.0
    spec.visual.headlight.ambient = [0.25, 0.25, 0.25]
    spec.visual.headlight.diffuse = [0.3, 0.3, 0.3]
    spec.visual.quality.offsamples = 4 if cams.antialias else 0
    spec.visual.quality.shadowsize = 2048 if cams.shadows else 0
    spec.visual.global_.offwidth = max(640, cams.width)
    spec.visual.global_.offheight = max(480, cams.height)
    spec.visual.map.znear = 0.01
    spec.stat.extent = 2.0
    spec.stat.center = [-0.1, 0.0, 0.3]
    return spec


def add_table(spec: mujoco.MjSpec, table_min: tuple[float, float],
              table_max: tuple[float, float]) -> None:
    """The ``floor`` and a ``table`` (top surface z = 0, extent ``table_min``..``table_max``
    in x, y [m]) on four legs, as on the tabletop."""
    floor = spec.worldbody.add_body(name="floor")
    add_geom(floor, "floor_geom", "box", (3.0, 3.0, 0.05), (0.0, 0.0, FLOOR_Z - 0.05),
             (0.35, 0.33, 0.30, 1.0))
    table = spec.worldbody.add_body(name="table")
    lo, hi = np.asarray(table_min), np.asarray(table_max)
    centre, half = (lo + hi) / 2, (hi - lo) / 2
    add_geom(table, "table_top", "box", (half[0], half[1], 0.02), (centre[0], centre[1], -0.02),
             (0.78, 0.70, 0.58, 1.0))
    leg_h = (-FLOOR_Z - 0.04) / 2
    for k, (sx, sy) in enumerate(((-1, -1), (-1, 1), (1, -1), (1, 1))):
        pos = (centre[0] + sx * (half[0] - 0.05), centre[1] + sy * (half[1] - 0.05), -0.04 - leg_h)
        add_geom(table, f"table_leg_{k}", "box", (0.025, 0.025, leg_h), pos,
                 (0.45, 0.40, 0.33, 1.0))


def add_cameras_and_lights(spec: mujoco.MjSpec, cams: CameraConfig) -> None:
    """Cameras ``<name>_camera`` aimed at ``cams.target`` and three lights from the robot's side."""
    world = spec.worldbody
    target = np.asarray(cams.target, dtype=np.float64)
    for name, pos in cams.positions:
        p = np.asarray(pos, dtype=np.float64)
        world.add_camera(name=f"{name}_camera", pos=p.tolist(),
                         quat=look_at_quat(p, target).tolist(), fovy=cams.fovy)
    for k, pos in enumerate(((-1.0, -0.8, 2.2), (-1.0, 0.8, 2.2), (-1.6, 0.0, 1.2))):
        light = world.add_light(name=f"light_{k}", pos=list(pos),
                                dir=(target - np.asarray(pos)).tolist())
        light.diffuse = [0.3, 0.3, 0.3]
        light.specular = [0.1, 0.1, 0.1]
        light.castshadow = cams.shadows and k == 0


__all__ = ["DARK_METAL", "GLASS", "METAL", "PAINT", "WOOD", "GeomKind", "add_cameras_and_lights",
           "add_geom", "add_part_site", "add_table", "new_spec"]
