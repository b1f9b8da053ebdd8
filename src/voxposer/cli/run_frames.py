"""``voxposer run --frames DIR --robot none "<instruction>"``: plan on recorded RGB-D frames.

The language model programs and the planner run on a folder of frames
(:mod:`voxposer.perception.frames`, e.g. from ``voxposer render --save-frames``) read by the
pixel perception (``colour-depth``; ``ground-truth`` only for frames saved with their labels),
and no robot moves: the "plan" is the first sub-task's planned path from the end-effector pose
recorded with the frames (:mod:`voxposer.control.plan_only`). The output folder gets
``subtask_01.html`` (composed maps and planned path), ``plan.json`` (the path's waypoints),
``transcript.jsonl`` and ``summary.json``; exit status 0 when the first sub-task was planned.
``--register-cameras`` registers the recorded cameras against each other first
(:mod:`voxposer.perception.view_registration`; the corrections' sizes go to ``summary.json``).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from voxposer import tabletop
from voxposer.errors import ConfigError

if TYPE_CHECKING:
    from voxposer.perception.frames import RecordedFrames
    from voxposer.perception.perceiver import ObservationSource, Perceiver
    from voxposer.pipeline import Embodiment

#: ``--robot`` values: the simulated arm, or none (with ``--frames``: plan only).
ROBOTS = ("sim", "none")
#: ``--perception`` values that can read recorded frames.
FRAME_PERCEPTIONS = ("colour-depth", "ground-truth", "open-vocab")


def add_frame_options(parser: argparse.ArgumentParser) -> None:
    """The ``recorded frames`` option group of ``voxposer run``."""
    group = parser.add_argument_group("recorded frames")
    group.add_argument("--frames", type=Path, default=None, metavar="DIR",
                       help="plan on recorded RGB-D frames (voxposer render --save-frames) "
                       "instead of the simulator; needs --robot none")
    group.add_argument("--robot", choices=ROBOTS, default="sim",
                       help="what executes: the simulated arm (sim, default) or nothing (none: "
                       "plan the first sub-task only; with --frames)")
    group.add_argument("--register-cameras", action="store_true",
                       help="with --frames: register the cameras against each other before "
                       "perceiving (multi-view ICP and the tops of objects on the table, world "
                       "z = 0 at the table top), for a rig whose extrinsics are a few mm or "
                       "tenths of a degree off; kept as recorded when the scene shows fewer "
                       "than two such tops to every camera")


def check_frame_options(args: argparse.Namespace) -> None:
    """Refuse ``--robot`` / ``--frames`` combinations that mean nothing, and unreadable frames;
    set ``args.perception``'s default (colour-depth on frames, else ground-truth).

    Raises:
        ConfigError: ``--robot none`` without ``--frames``, ``--frames`` with ``--robot sim``,
            a simulator-only option with ``--frames``, a perception the frames cannot serve,
            or a bad frames folder (naming the file).
    """
    frames = getattr(args, "frames", None)
    robot = getattr(args, "robot", "sim")
    if frames is None:
        if getattr(args, "register_cameras", False):
            raise ConfigError("--register-cameras registers recorded cameras: add --frames DIR "
                              "(the simulated perceptions with sensor noise register theirs)")
        if robot == "none":
            raise ConfigError("--robot none plans without moving a robot, on recorded frames: "
                              "add --frames DIR (voxposer render --save-frames DIR writes some)")
        args.perception = args.perception or "ground-truth"
        return
    if robot != "none":
        raise ConfigError(f"--frames {str(frames)!r} are recorded views with no robot to move; "
                          "add --robot none (plans the first sub-task, moves nothing)")
    for flag, value in (("--disturb", args.disturb), ("--drawer-open", args.drawer_open),
                        ("--place", args.place)):
        if value:
            raise ConfigError(f"{flag} changes the simulated scene; recorded --frames have none")
    from voxposer.perception.frames import RecordedFrames

    source = RecordedFrames(frames)
    args.perception = args.perception or "colour-depth"
    if args.perception not in FRAME_PERCEPTIONS:
        raise ConfigError(f"--perception {args.perception} is not for recorded frames (they "
                          f"carry their camera's own noise); choose {' or '.join(FRAME_PERCEPTIONS)}")
    if args.perception == "ground-truth" and not source.has_labels:
        raise ConfigError(f"--perception ground-truth needs labels, and {frames} has none "
                          "(saved without --with-labels); use --perception colour-depth")


def frames_embodiment(frames: Path, perception: str, args: argparse.Namespace | None = None
                      ) -> tuple[RecordedFrames, Embodiment]:
    """The frames folder ``frames`` and the embodiment reading it: the stub robot reporting the
    recorded pose, and the ``perception`` perceiver on the tabletop workspace grid
    (:data:`voxposer.tabletop.WORKSPACE_MIN` … ``WORKSPACE_MAX``, ``GRID_SHAPE`` voxels),
    reading the frames through
    :class:`~voxposer.perception.view_registration.RegisteredObservationSource` when
    ``args.register_cameras``."""
    from voxposer.control.plan_only import RecordedPoseRobot
    from voxposer.geometry.voxel_grid import VoxelGrid
    from voxposer.perception.colour_depth import ColourDepthPerceiver
    from voxposer.perception.frames import RecordedFrames
    from voxposer.perception.segmentation import SegmentationPerceiver
    from voxposer.pipeline import Embodiment

    source = RecordedFrames(frames)
    grid = VoxelGrid(tabletop.WORKSPACE_MIN, tabletop.WORKSPACE_MAX, tabletop.GRID_SHAPE)
    seen: ObservationSource = source
    if getattr(args, "register_cameras", False):
        from voxposer.perception.view_registration import RegisteredObservationSource

        seen = RegisteredObservationSource(source, grid)
    perceiver: Perceiver
    if perception == "open-vocab" and args is not None:
        from voxposer.cli.perception_options import open_vocab_from_args

        perceiver = open_vocab_from_args(seen, grid, args)
    elif perception == "colour-depth":
        perceiver = ColourDepthPerceiver(seen, grid)
    else:
        perceiver = SegmentationPerceiver(seen, grid)
    robot = RecordedPoseRobot(source.observation, source.gripper_opening_m)
    return source, Embodiment(robot, perceiver)


def rollout_frames(args: argparse.Namespace, backend: Any, out: Path,
                   summary: dict[str, Any]) -> None:
    """Run the programs on ``args.frames`` with ``backend`` and plan the first sub-task; fill
    ``summary`` (and write ``plan.json``) as it goes."""
    from voxposer.control.plan_only import PlanOnlyHandoff
    from voxposer.lmp.runtime import LMPRuntime
    from voxposer.lmp.transcript import Transcript

    source, body = frames_embodiment(args.frames, args.perception, args)
    perceiver = body.perceiver
    summary.update(robot="none", frames=str(args.frames), model=backend.model,
                   scene={"frames": str(args.frames),
                          "cameras": [c.name for c in source.observation.cameras]})
    handoff = PlanOnlyHandoff(body.robot, perceiver, np.random.default_rng(args.seed),
                              picture_dir=out)
    runtime = LMPRuntime(body.scene, backend, handoff,
                         transcript=Transcript(out / "transcript.jsonl"))
    try:
        runtime.run(args.instruction)
    finally:
        summary["llm_calls"] = runtime.llm_calls
        summary["scene"]["objects_seen"] = list(perceiver.object_names)
        corrections = getattr(getattr(perceiver, "source", None), "corrections", None)
        if getattr(args, "register_cameras", False) and corrections is not None:
            summary["scene"]["camera_corrections"] = _correction_sizes(corrections)
        summary["subtasks"] = [_planned(r) for r in handoff.records] + [
            {"subtask": s, "planned": False} for s in handoff.skipped]
        backend.close()
    first = handoff.records[0] if handoff.records else None
    if first is None or first.result.first_plan is None:
        summary.update(success=False, reason=first.result.reason if first else "nothing_planned",
                       message=first.result.message if first else
                       "the programs never called execute()")
        return
    plan = first.result.first_plan
    (out / "plan.json").write_text(json.dumps(plan_json(first.subtask, first.result.entity,
                                                        plan), indent=1))
    summary.update(success=True, reason="planned",
                   message=f"planned {first.subtask!r}: {len(plan.trajectory)} waypoints to "
                   f"{np.round(plan.target, 3).tolist()} m; not executed (--robot none)")


def _correction_sizes(corrections: dict[str, Any]) -> dict[str, dict[str, float]]:
    """Camera name → the size of its registration correction (rotation [deg], translation at
    the world origin [mm]); zeros when the cameras were kept as recorded."""
    from voxposer.perception.surface_registration import correction_size

    sizes = {name: correction_size(m) for name, m in corrections.items()}
    return {name: {"rotation_deg": round(deg, 3), "translation_mm": round(shift * 1000, 2)}
            for name, (deg, shift) in sizes.items()}


def _planned(record: Any) -> dict[str, Any]:
    """One planned sub-task as ``summary.json`` lists it."""
    r = record.result
    return {"subtask": record.subtask, "planned": r.first_plan is not None, "entity": r.entity,
            "reason": "planned" if r.first_plan is not None else r.reason,
            "message": r.message, "picture": record.picture.name if record.picture else None}


def plan_json(subtask: str, entity: str, plan: Any) -> dict[str, Any]:
    """``plan.json``: the planned path of ``entity`` [m], its orientations (x, y, z, w), gripper
    commands (1 closed) and speed scales, one per waypoint; whether it ends on the target."""
    traj = plan.trajectory
    return {"subtask": subtask, "entity": entity, "reached": bool(plan.reached),
            "method": plan.method, "start_m": traj.positions[0].round(5).tolist(),
            "target_m": plan.target.round(5).tolist(),
            "waypoints_m": traj.positions.round(5).tolist(),
            "quaternions_xyzw": traj.quaternions.round(5).tolist(),
            "gripper": traj.gripper.tolist(), "velocity_scales": traj.velocity_scales.tolist()}


__all__ = ["FRAME_PERCEPTIONS", "ROBOTS", "add_frame_options", "check_frame_options",
           "frames_embodiment", "plan_json", "rollout_frames"]
