"""Offscreen RGB-D + segmentation rendering of the scene's fixed cameras (EGL by default).

Each camera is rendered in two passes sharing one scene update: a colour pass (RGB) and a
segmentation pass whose colours encode geom ids and whose depth buffer gives metric depth.

Frames are :class:`voxposer.perception.observation.CameraFrame` (OpenCV camera axes); the
segmentation pass also fills its ``object_ids`` channel with ground-truth catalog labels.
"""

from __future__ import annotations

import importlib
import os

os.environ.setdefault("MUJOCO_GL", "egl")

import math
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from voxposer.catalog import NO_OBJECT
from voxposer.perception.observation import CameraFrame

_CV_FROM_GL = np.diag([1.0, -1.0, -1.0])


def _gl_context(width: int, height: int) -> Any:
    """An offscreen GL context for the backend named by ``MUJOCO_GL`` (EGL unless set).

    Chosen explicitly here because mujoco picks its default backend when first imported, which
    may happen (e.g. through mink) before this module could set ``MUJOCO_GL``.
    """
    backend = os.environ.get("MUJOCO_GL", "egl").lower()
    module = {"egl": "mujoco.egl", "osmesa": "mujoco.osmesa"}.get(backend, "mujoco.gl_context")
    return importlib.import_module(module).GLContext(width, height)


def intrinsics_matrix(width: int, height: int, fovy_deg: float) -> NDArray[np.float64]:
    """Pinhole K, shape (3, 3), of a MuJoCo camera with vertical field of view ``fovy_deg``."""
    f = (height / 2.0) / math.tan(math.radians(fovy_deg) / 2.0)
    return np.array([[f, 0.0, (width - 1) / 2.0], [0.0, f, (height - 1) / 2.0], [0.0, 0.0, 1.0]])


class CameraRenderer:
    """Renders fixed cameras of one model; holds a GL context (release it with :meth:`close`).

    Args:
        model: the compiled scene (its ``vis.global_.offwidth/offheight`` bound the image size).
        geom_labels: scene-object label per geom, shape (ngeom,).
        shadows: render shadows in the colour pass.
        detailed_robot: draw the robot's visual meshes (group 1); otherwise its low-poly
            collision meshes (group 3) stand in for them, about 4x faster on a CPU renderer.
        depth_max: depths beyond this [m] become ``inf`` (background).
    """

    def __init__(self, model: mujoco.MjModel, geom_labels: NDArray[np.int32], *,
                 shadows: bool = False, detailed_robot: bool = False,
                 depth_max: float = 4.0) -> None:
        self._model = model
        self._max_w = int(model.vis.global_.offwidth)
        self._max_h = int(model.vis.global_.offheight)
        self._gl: Any = _gl_context(self._max_w, self._max_h)
        self._gl.make_current()
        self._con = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150.value)
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN.value, self._con)
        self._con.readDepthMap = mujoco.mjtDepthMap.mjDEPTH_ZEROFAR
        self._scene = mujoco.MjvScene(model, maxgeom=2000)
        self._option = mujoco.MjvOption()
        self._option.geomgroup[1] = detailed_robot
        self._option.geomgroup[3] = not detailed_robot
        self._camera = mujoco.MjvCamera()
        self._camera.type = mujoco.mjtCamera.mjCAMERA_FIXED
        self._labels = np.concatenate([np.asarray(geom_labels, np.int32), [NO_OBJECT]])
        self.shadows = shadows
        self.depth_max = depth_max
        extent = model.stat.extent
        self._near = np.float32(model.vis.map.znear * extent)
        self._far = np.float32(model.vis.map.zfar * extent)

    def close(self) -> None:
        """Free the GL resources (idempotent)."""
        if self._gl is not None:
            self._gl.make_current()
            self._con.free()
            self._gl.free()
            self._gl = None

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:
            pass

    def _metric_depth(self, buffer: NDArray[np.float32]) -> NDArray[np.float32]:
        # Reverse-Z perspective depth buffer → distance along the optical axis (as mujoco.Renderer).
        near, far = self._near, self._far
        c = np.float32(-0.5) * (-(far + near) / (far - near)) - np.float32(0.5)
        d = np.float32(-0.5) * (-(np.float32(2) * far * near) / (far - near))
        depth = (d / (buffer.astype(np.float64) + c)).astype(np.float32)
        depth[(depth > self.depth_max) | ~np.isfinite(depth)] = np.inf
        return depth

    def render(self, data: mujoco.MjData, camera: str, width: int, height: int,
               *, segmentation: bool = True, colour: bool = True, depth: bool = True
               ) -> CameraFrame:
        """Render ``camera`` (a name from the model, e.g. ``"front_left_camera"``).

        With ``segmentation=False`` only the colour pass runs, its depth read with the colour
        (the same depth as the segmentation pass's; ``depth=False``: left empty) and the ids
        left empty — what a perception from pixels needs, at about half the cost of both
        passes; with ``colour=False`` only the depth/segmentation pass runs (``rgb`` is black).
        """
        if self._gl is None:
            raise RuntimeError("CameraRenderer.render called after close()")
        if not (0 < width <= self._max_w and 0 < height <= self._max_h):
            raise ValueError(f"image size {width}x{height} exceeds the offscreen buffer "
                             f"{self._max_w}x{self._max_h}")
        cam_id = mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_CAMERA, camera)
        if cam_id < 0:
            names = [self._model.camera(i).name for i in range(self._model.ncam)]
            raise ValueError(f"unknown camera {camera!r}; cameras are: {', '.join(names)}")
        self._gl.make_current()
        self._camera.fixedcamid = cam_id
        scn = self._scene
        mujoco.mjv_updateScene(self._model, data, self._option, None, self._camera,
                               mujoco.mjtCatBit.mjCAT_ALL.value, scn)
        rect = mujoco.MjrRect(0, 0, width, height)
        flags = scn.flags
        flags[mujoco.mjtRndFlag.mjRND_SHADOW] = self.shadows
        flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = False
        flags[mujoco.mjtRndFlag.mjRND_SKYBOX] = False
        metric = np.full((height, width), np.inf, dtype=np.float32)
        if colour or not segmentation:
            rgb = np.empty((height, width, 3), dtype=np.uint8)
            zbuf = np.empty((height, width), dtype=np.float32) if depth and not segmentation \
                else None
            mujoco.mjr_render(rect, scn, self._con)
            mujoco.mjr_readPixels(rgb, zbuf, rect, self._con)
            rgb = np.ascontiguousarray(rgb[::-1])
            if zbuf is not None:
                zbuf = zbuf[::-1]
                metric = self._metric_depth(zbuf)
                metric[zbuf <= 0] = np.inf  # nothing drawn (reverse-Z clears to 0)
        else:
            rgb = np.zeros((height, width, 3), dtype=np.uint8)
        seg = np.full((height, width, 2), -1, dtype=np.int32)
        ids = np.full((height, width), NO_OBJECT, dtype=np.int32)
        if segmentation:
            flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = True
            flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = True
            code = np.empty((height, width, 3), dtype=np.uint8)
            zbuf = np.empty((height, width), dtype=np.float32)
            mujoco.mjr_render(rect, scn, self._con)
            mujoco.mjr_readPixels(code, zbuf, rect, self._con)
            flags[mujoco.mjtRndFlag.mjRND_SEGMENT] = False
            flags[mujoco.mjtRndFlag.mjRND_IDCOLOR] = False
            code = code[::-1].astype(np.int32)
            segid = code[..., 0] + (code[..., 1] << 8) + (code[..., 2] << 16)
            lut = np.full((scn.ngeom + 1, 2), -1, dtype=np.int32)
            for g in scn.geoms[: scn.ngeom]:
                if g.segid != -1:
                    lut[g.segid + 1] = (g.objid, g.objtype)
            seg = lut[np.minimum(segid, scn.ngeom)]
            metric = self._metric_depth(zbuf[::-1])
            is_geom = seg[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM)
            ids = np.where(is_geom, self._labels[np.where(is_geom, seg[..., 0], -1)], NO_OBJECT)
            ids = ids.astype(np.int32)
            metric[segid == 0] = np.inf
        return CameraFrame(
            name=camera.removesuffix("_camera"),
            rgb=rgb,
            depth=metric,
            intrinsics=intrinsics_matrix(width, height, float(self._model.cam_fovy[cam_id])),
            extrinsics=self.extrinsics(data, cam_id),
            object_ids=ids,
        )

    @staticmethod
    def extrinsics(data: mujoco.MjData, cam_id: int) -> NDArray[np.float64]:
        """Camera-to-world transform, shape (4, 4), with OpenCV axes (z forward, y down)."""
        pose = np.eye(4)
        pose[:3, :3] = data.cam_xmat[cam_id].reshape(3, 3) @ _CV_FROM_GL
        pose[:3, 3] = data.cam_xpos[cam_id]
        return pose
