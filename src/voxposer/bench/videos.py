"""``--video none|failures|all``: an MP4 of each episode, to look at what went wrong.

With ``failures`` or ``all`` each episode is recorded while it runs, with
:class:`~voxposer.control.recording.VideoRecorder` (one camera, :data:`FPS` frames per simulated
second, :data:`WIDTH` × :data:`HEIGHT` pixels), into ``<out>/videos/<identity>.mp4`` (the
record's identity: method, llm, instruction split, task, attribute split, seed, and
``disturbed`` for disturbed episodes). With ``failures`` the file of a successful episode is
deleted. The record's ``video`` field is the path relative to the output folder, or None.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, Protocol

from voxposer.errors import ConfigError

if TYPE_CHECKING:
    from voxposer.control.recording import VideoRecorder


class VideoJob(Protocol):
    """What names and places an episode's video (an :class:`~voxposer.bench.episode.EpisodeJob`)."""

    @property
    def method(self) -> str: ...
    @property
    def llm(self) -> str: ...
    @property
    def instructions(self) -> str: ...
    @property
    def task(self) -> str: ...
    @property
    def split(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def disturbed(self) -> bool: ...
    @property
    def video(self) -> str: ...
    @property
    def out_dir(self) -> str | None: ...

log = logging.getLogger(__name__)

#: the ``--video`` values.
VIDEO_MODES: Final = ("none", "failures", "all")
#: the videos' folder, inside the output folder.
VIDEO_DIR: Final = "videos"
#: frame size [pixels] (multiples of 16 encode without resizing) and rate [frames per sim s].
WIDTH: Final = 320
HEIGHT: Final = 240
FPS: Final = 10
CAMERA: Final = "front_left"


def check_video_mode(mode: str) -> str:
    """``mode`` if it is a ``--video`` value; ConfigError listing the allowed ones if not."""
    if mode not in VIDEO_MODES:
        raise ConfigError(f"unknown video mode {mode!r}; choose one of: {', '.join(VIDEO_MODES)}")
    return mode


def video_name(job: VideoJob) -> str:
    """``<method>-<llm>-<instructions>-<task>-<split>-<seed>[-disturbed].mp4``: unique per
    record identity."""
    name = f"{job.method}-{job.llm}-{job.instructions}-{job.task}-{job.split}-{job.seed}"
    return name + ("-disturbed" if job.disturbed else "") + ".mp4"


def start_video(job: VideoJob, world: Any) -> VideoRecorder | None:
    """Start recording ``job``'s episode in ``world`` (None with ``video="none"``).

    Raises:
        ConfigError: a video is asked for but the job has no output folder.
    """
    if check_video_mode(job.video) == "none":
        return None
    if job.out_dir is None:
        raise ConfigError(f"video={job.video!r} needs EpisodeJob.out_dir (the output folder)")
    from voxposer.control.recording import VideoRecorder

    path = Path(job.out_dir) / VIDEO_DIR / video_name(job)
    return VideoRecorder(world, path, camera=CAMERA, fps=FPS, width=WIDTH, height=HEIGHT)


def finish_video(job: VideoJob, recorder: VideoRecorder | None, success: bool) -> str | None:
    """Close ``recorder``; keep the file unless ``video="failures"`` and the episode succeeded.

    Returns:
        The kept file's path relative to the output folder (``videos/….mp4``), or None.
    """
    if recorder is None:
        return None
    path = recorder.close()
    if job.video == "failures" and success:
        path.unlink(missing_ok=True)
        return None
    return f"{VIDEO_DIR}/{path.name}"
