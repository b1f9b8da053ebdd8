"""An MP4 of a rollout, recorded from one camera as the simulation advances."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

import imageio.v2 as imageio

log = logging.getLogger(__name__)


class VideoRecorder:
    """Writes a frame every ``1 / fps`` simulated seconds while attached to a world.

    Frames are appended to the MP4 as they are rendered (an interrupted run keeps what it
    recorded up to the last flushed frame). Use as a context manager or call :meth:`close`.

    Args:
        world: a world with ``render(camera, width, height)``, ``data.time`` and
            ``step_callbacks`` (:class:`voxposer.envs.TabletopWorld`).
        path: the MP4 file to write.
        camera: camera name (e.g. ``"front_left"``).
        fps: frames per simulated second (the video plays in real time).
        width, height: frame size [pixels] (multiples of 16 encode without resizing).
    """

    def __init__(
        self,
        world: Any,
        path: str | Path,
        camera: str = "front_left",
        fps: int = 10,
        width: int = 480,
        height: int = 352,
    ) -> None:
        self.world = world
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.camera, self.fps, self.width, self.height = camera, fps, width, height
        self.frames = 0
        self._writer = imageio.get_writer(
            self.path, fps=fps, codec="libx264", quality=7, macro_block_size=16
        )
        self._next = float(world.data.time)
        world.step_callbacks.append(self._on_advance)
        self.capture()

    def capture(self) -> None:
        """Append the current view as a frame."""
        self._writer.append_data(self.world.render(self.camera, self.width, self.height))
        self.frames += 1

    def _on_advance(self, world: Any) -> None:
        if float(world.data.time) + 1e-9 >= self._next:
            self.capture()
            self._next = float(world.data.time) + 1.0 / self.fps

    def close(self) -> Path:
        """Detach from the world and finish the file."""
        if self._on_advance in self.world.step_callbacks:
            self.world.step_callbacks.remove(self._on_advance)
        self._writer.close()
        log.info("wrote %s (%d frames)", self.path, self.frames)
        return self.path

    def __enter__(self) -> VideoRecorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
