"""A Gymnasium wrapper of :class:`~voxposer.envs.world.TabletopWorld`.

Action, shape (8,), float64: end-effector target position [m] (3), quaternion (x, y, z, w) (4),
gripper (1: closed, 0: open). One ``step`` runs one controller period toward the target (see
:meth:`TabletopWorld.step`). Observation: a dict of ``ee_position`` (3,), ``ee_quat`` (4,),
``gripper`` (1,) and, when ``images=True``, ``rgb`` (n_cameras, H, W, 3) and ``depth``
(n_cameras, H, W) [m]. The episode never terminates on its own; it is truncated after
``max_steps``. Reward is always 0 (tasks add their own).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces
from numpy.typing import NDArray

from voxposer.envs.config import WorldConfig
from voxposer.envs.layout import SceneLayout
from voxposer.envs.world import TabletopWorld
from voxposer.errors import ConfigError, InvalidActionError


class TabletopEnv(gym.Env[dict[str, NDArray[Any]], NDArray[np.float64]]):
    """Gymnasium environment over the tabletop world (see the module docstring).

    Args:
        config: world configuration.
        images: include camera images in observations (slower: renders every step).
        max_steps: steps before ``truncated`` is set.
        layout: scene layout used at every reset; ``options={"layout": ...}`` overrides it.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}  # noqa: RUF012 - gymnasium's way

    def __init__(self, config: WorldConfig | None = None, *, images: bool = False,
                 max_steps: int = 500, layout: SceneLayout | None = None,
                 render_mode: str | None = None) -> None:
        if max_steps < 1:
            raise ConfigError(f"TabletopEnv.max_steps must be >= 1; got {max_steps!r}")
        if render_mode not in (None, "rgb_array"):
            raise ConfigError(f"TabletopEnv.render_mode must be None or 'rgb_array'; got {render_mode!r}")
        self.world = TabletopWorld(config)
        self.images = images
        self.max_steps = max_steps
        self.layout = layout
        self.render_mode = render_mode
        self._steps = 0
        grid = self.world.grid
        lo = np.concatenate([grid.bounds_min, -np.ones(4), [0.0]])
        hi = np.concatenate([grid.bounds_max, np.ones(4), [1.0]])
        self.action_space = spaces.Box(lo, hi, dtype=np.float64)
        obs: dict[str, spaces.Space[Any]] = {
            "ee_position": spaces.Box(-np.inf, np.inf, (3,), np.float64),
            "ee_quat": spaces.Box(-1.0, 1.0, (4,), np.float64),
            "gripper": spaces.Box(0.0, 1.0, (1,), np.float64),
        }
        if images:
            cams = self.world.config.cameras
            n, h, w = len(cams.names), cams.height, cams.width
            obs["rgb"] = spaces.Box(0, 255, (n, h, w, 3), np.uint8)
            obs["depth"] = spaces.Box(0.0, np.inf, (n, h, w), np.float32)
        self.observation_space = spaces.Dict(obs)  # type: ignore[assignment]

    def _observation(self) -> dict[str, NDArray[Any]]:
        pos, quat = self.world.get_ee_pose()
        if quat[3] < 0:
            quat = -quat
        out: dict[str, NDArray[Any]] = {
            "ee_position": pos,
            "ee_quat": quat,
            "gripper": np.array([self.world.get_gripper_state()]),
        }
        if self.images:
            obs = self.world.observe()
            out["rgb"] = np.stack([f.rgb for f in obs.cameras])
            out["depth"] = np.stack([f.depth for f in obs.cameras])
        return out

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None
              ) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
        """Reset the world from ``self.np_random`` (seeded by ``seed``)."""
        super().reset(seed=seed)
        layout = (options or {}).get("layout", self.layout)
        placement = self.world.reset(self.np_random, layout)
        self._steps = 0
        return self._observation(), {"placement": placement}

    def step(self, action: NDArray[np.float64]
             ) -> tuple[dict[str, NDArray[Any]], float, bool, bool, dict[str, Any]]:
        """One controller period toward the pose in ``action`` (see the module docstring)."""
        act = np.asarray(action, dtype=np.float64).reshape(-1)
        if act.shape != (8,):
            raise InvalidActionError(f"action must have 8 entries (pos 3, quat xyzw 4, gripper 1); "
                                     f"got shape {np.shape(action)}")
        result = self.world.step(act[:3], act[3:7], gripper=float(act[7]))
        self._steps += 1
        info = {"at_goal": result.at_goal, "time": result.time}
        return self._observation(), 0.0, False, self._steps >= self.max_steps, info

    def render(self) -> NDArray[np.uint8] | None:
        """RGB of the first camera when ``render_mode="rgb_array"``."""
        if self.render_mode != "rgb_array":
            return None
        return self.world.render(self.world.camera_names[0])

    def close(self) -> None:
        """Release the rendering context."""
        self.world.close()
