"""The cameras' side of a simulated world: rendering and cached RGB-D observations.

A mixin of both worlds (:class:`voxposer.envs.world.TabletopWorld` and
:class:`voxposer.envs.articulated.world.ArticulatedWorld`): it renders the configured cameras
with a ground-truth label channel and the robot's state into an
:class:`~voxposer.perception.observation.Observation`, cached until the physics state changes, so
several perception queries at one instant render the cameras once. Each world says what its
labels are (:meth:`CameraViewsMixin._geom_label_ids`, :meth:`CameraViewsMixin._label_names`).

With a camera frame rate (``CameraConfig.frame_hz``) each camera renders only when its next
frame is due — camera k of N at the times (n - k / N) / frame_hz — and an observation holds the
latest frame of each, as a robot's camera streams do; the robot's state is always current.
"""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from voxposer.envs.arm import ArmSettings, ArmStateMixin
from voxposer.envs.cameras import CameraRenderer
from voxposer.envs.config import CameraConfig
from voxposer.perception.observation import CameraFrame, Observation

#: a frame due at a slot boundary is new even with rounding in the simulated clock [slots]
_SLOT_EPS = 1e-6


def _frame_slot(time_s: float, frame_hz: float, index: int, cameras: int) -> int:
    """Which frame period of camera ``index`` (of ``cameras``) simulated time ``time_s`` [s]
    falls in; the cameras' periods are shifted by 1/``cameras`` of a period each."""
    return math.floor(time_s * frame_hz + index / cameras + _SLOT_EPS)


class _WorldSettings(ArmSettings, Protocol):
    """What the views read of the world's configuration (the arm's settings and the cameras)."""

    @property
    def cameras(self) -> CameraConfig: ...


class CameraViewsMixin(ArmStateMixin):
    """Rendering and observation (needs the attributes declared below, and the two label hooks)."""

    config: _WorldSettings
    _renderer: CameraRenderer | None
    _obs: Observation | None
    _obs_key: tuple[float, int, int, bool, bool] | None

    def _geom_label_ids(self) -> NDArray[np.int32]:
        """Label id of every geom, shape (ngeom,), indexing :meth:`_label_names`; -1 for none."""
        raise NotImplementedError

    def _label_names(self) -> tuple[str, ...]:
        """Names of the label ids of the segmentation channel."""
        raise NotImplementedError

    @property
    def camera_names(self) -> tuple[str, ...]:
        """The cameras, e.g. ``("front_left", "front_right", "back_left", "back_right")``."""
        return self.config.cameras.names

    def _camera_renderer(self) -> CameraRenderer:
        if self._renderer is None:
            cams = self.config.cameras
            self._renderer = CameraRenderer(self.model, self._geom_label_ids(),
                                            shadows=cams.shadows, depth_max=cams.depth_max,
                                            detailed_robot=cams.detailed_robot)
        return self._renderer

    def render(self, camera: str, width: int | None = None, height: int | None = None
               ) -> NDArray[np.uint8]:
        """RGB image, shape (height, width, 3), of ``camera`` (e.g. ``"front_left"``)."""
        cams = self.config.cameras
        frame = self._camera_renderer().render(
            self.data, f"{camera.removesuffix('_camera')}_camera", width or cams.width,
            height or cams.height, segmentation=False, depth=False)
        return frame.rgb

    def observe(self, width: int | None = None, height: int | None = None, *,
                rgb: bool = True, labels: bool = True) -> Observation:
        """All camera views (RGB, depth [m], intrinsics, extrinsics, ground-truth label ids)
        and the robot's state. Cached until the state changes.

        ``rgb=False`` skips the colour pass (images are black): enough for planning and
        detection from the label ids, about half the rendering time. ``labels=False`` skips
        the ground-truth segmentation pass instead (ids all -1, depth read with the colour):
        what a perception from pixels needs, also about half. An observation also serves later
        requests at the same instant that ask for no more than it holds.
        """
        cams = self.config.cameras
        w, h = width or cams.width, height or cams.height
        key = (float(self.data.time), w, h)
        old = self._obs_key
        if self._obs is not None and old is not None and old[:3] == key and (
                old[3] or not rgb) and (old[4] or not labels):
            return self._obs
        if not labels:  # the colour pass renders the depth (and the colour with it)
            rgb = True
        frames = tuple(self._latest_frame(k, name, w, h, rgb, labels)
                       for k, name in enumerate(cams.names))
        pos, quat = self.get_ee_pose()
        self._obs = Observation(time=float(self.data.time), cameras=frames, ee_position=pos,
                                ee_quat=quat, gripper=self._gripper,
                                label_names=self._label_names())
        self._obs_key = (*key, rgb, labels)
        return self._obs

    def _latest_frame(self, index: int, name: str, width: int, height: int,
                      rgb: bool, labels: bool) -> CameraFrame:
        """Camera ``name``'s (the ``index``-th camera's) frame for an observation now: without a
        frame rate a new one; with one, its last frame while no new frame is due (same image
        size, colour and labels when asked), else a new one."""
        cams = self.config.cameras
        camera = f"{name}_camera"

        def render() -> CameraFrame:
            return self._camera_renderer().render(self.data, camera, width, height, colour=rgb,
                                                  segmentation=labels)

        if cams.frame_hz is None:
            return render()
        now = float(self.data.time)
        held: dict[str, tuple[float, tuple[int, int, bool, bool], CameraFrame]] = (
            self.__dict__.setdefault("_camera_frames", {}))
        last = held.get(name)
        if last is not None:
            when, (w, h, colour, labelled), frame = last
            slots = (_frame_slot(t, cams.frame_hz, index, len(cams.names)) for t in (when, now))
            if when <= now and len(set(slots)) == 1 and (w, h) == (width, height) and (
                    colour or not rgb) and (labelled or not labels):
                return frame
        frame = render()
        held[name] = (now, (width, height, rgb, labels), frame)
        return frame

    def close(self) -> None:
        """Release the rendering context (the world stays usable; rendering reopens it)."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
