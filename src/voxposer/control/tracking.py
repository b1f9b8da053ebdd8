"""Following a planned trajectory with the robot's pose controller for a replanning period."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from voxposer.control.execution_result import ExecutionResult
from voxposer.planning.trajectory import Trajectory
from voxposer.robot import Robot


def follow(robot: Robot, traj: Trajectory, steps: int, result: ExecutionResult,
           shift: NDArray[np.float64], lookahead_m: float) -> None:
    """Steer ``robot`` along ``traj`` (planned for a point ``shift`` metres from the hand, e.g. a
    carried object's centre) for ``steps`` control periods, appending the hand's positions and
    times to ``result.trace`` / ``trace_time``.

    Each period commands the trajectory point ``lookahead_m`` [m] of arc length ahead of the
    point nearest the hand (further ahead when the velocity map asks for more than the default
    speed, or the arm's tracking lag would cap the speed), with that point's orientation,
    gripper command and velocity scale. Stops early at the trajectory's end.
    """
    pos = traj.positions - shift
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pos, axis=0), axis=1))])
    for _ in range(steps):
        here = robot.get_ee_pose()[0]
        near = int(np.argmin(np.linalg.norm(pos - here, axis=1)))
        lookahead = lookahead_m * max(1.0, float(traj.velocity_scales[near]))
        ahead = min(int(np.searchsorted(arc, arc[near] + lookahead)), len(pos) - 1)
        wp = traj[ahead]
        res = robot.step(wp.position - shift, wp.quaternion, gripper=float(traj.gripper[near]),
                         speed_scale=wp.velocity_scale)
        result.trace.append(np.asarray(res.ee_position, dtype=np.float64))
        result.trace_time.append(float(res.time))
        if res.at_goal and ahead == len(pos) - 1:
            break
