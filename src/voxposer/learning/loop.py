"""The learning loop of paper Sec. 3.4: collect transitions with MPC, train g_θ, evaluate, repeat.

One run is one (task, prior on/off, seed). Each iteration collects
``episodes_per_iteration`` episodes with the current model (the first with none: τ₀ + ε, or
uniform actions), retrains the MLP on every transition so far, and evaluates it on
``eval_episodes`` fixed resets. Interaction time is the simulated time of the collection
episodes (the evaluation episodes are neither counted nor trained on). The run stops when the
evaluation success reaches ``converged_success`` or the interaction time reaches the limit.

Everything is written as it goes under ``<out>/<task>/prior-<on|off>/seed-<k>/``: one JSONL line
per iteration, the transitions and the model's weights after each iteration; a run started
again continues after its last line.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from voxposer.errors import ConfigError, DivergedError
from voxposer.learning.policies import LearningPolicy, stage_orientations
from voxposer.learning.rollout import Episode, RolloutConfig, run_episode
from voxposer.learning.state import StateObserver
from voxposer.learning.task_cost import TaskCost, TaskCostConfig
from voxposer.learning.zero_shot import ZeroShotTrajectory
from voxposer.planning.dynamics.mlp import MLPConfig, MLPDynamics
from voxposer.planning.dynamics.training import Transitions, train
from voxposer.planning.waypoint_mpc import WaypointMPCConfig


@dataclass(frozen=True)
class LearnConfig:
    """Parameters of one learning run (paper Sec. 4.3; σ, budget and schedule are ours).

    Attributes:
        time_limit_s: simulated interaction budget [s] (the paper: under 3 minutes with prior).
        sigma_m: σ of the noise ε on each prior waypoint [m].
        gripper_sigma: σ of the noise on the prior's gripper command.
        episodes_per_iteration: collection episodes between two trainings.
        eval_episodes: evaluation episodes after each training.
        epochs_per_iteration: passes over all transitions per training.
        converged_success: evaluation success that ends the run.
        extra_steps: an episode lasts as many actions as its τ₀ has waypoints and this many
            more (in both arms: τ₀'s length is the task's time budget), at most
            ``rollout.max_steps``.
        n_samples: MPC samples per step.
        horizon: MPC horizon [actions].
        rollout: how actions are executed.
        mlp: the network.
        cost: the task cost's weights.
    """

    time_limit_s: float = 180.0
    sigma_m: float = 0.01
    gripper_sigma: float = 0.1
    episodes_per_iteration: int = 2
    eval_episodes: int = 3
    epochs_per_iteration: int = 30
    converged_success: float = 0.8
    extra_steps: int = 8
    n_samples: int = 1000
    horizon: int = 5
    rollout: RolloutConfig = field(default_factory=RolloutConfig)
    mlp: MLPConfig = field(default_factory=MLPConfig)
    cost: TaskCostConfig = field(default_factory=TaskCostConfig)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.time_limit_s) and self.time_limit_s > 0):
            raise ConfigError(f"the time limit must be > 0 seconds, got {self.time_limit_s!r}")
        for name in ("episodes_per_iteration", "eval_episodes", "epochs_per_iteration",
                     "n_samples", "horizon"):
            if getattr(self, name) < 1:
                raise ConfigError(f"LearnConfig.{name} must be >= 1, got {getattr(self, name)!r}")
        for name in ("sigma_m", "gripper_sigma"):
            if getattr(self, name) < 0:
                raise ConfigError(f"LearnConfig.{name} must be >= 0, got {getattr(self, name)!r}")

    def mpc(self) -> WaypointMPCConfig:
        """The MPC's sampling parameters."""
        r = self.rollout
        return WaypointMPCConfig(tuple(r.action_low), tuple(r.action_high),
                                 n_samples=self.n_samples, horizon=self.horizon,
                                 sigma=(self.sigma_m,) * 3 + (self.gripper_sigma,))


@dataclass(frozen=True)
class RunSpec:
    """Which run: ``task``, ``prior`` (sample around τ₀ or uniformly) and ``seed``."""

    task: str
    prior: bool
    seed: int

    def folder(self, out: Path) -> Path:
        """Where the run writes."""
        return out / self.task / f"prior-{'on' if self.prior else 'off'}" / f"seed-{self.seed}"


#: builds the world and the observer of a task, once per run
WorldFactory = Callable[[str], tuple[Any, StateObserver]]
#: called after every episode with (spec, iteration, kind "collect"/"eval", episode)
Progress = Callable[[RunSpec, int, str, Episode], None]


def _read_lines(path: Path) -> list[dict[str, Any]]:
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


@dataclass
class _Run:
    """The state a run carries from one iteration to the next."""

    spec: RunSpec
    config: LearnConfig
    trajectories: list[ZeroShotTrajectory]
    world: Any
    observer: StateObserver
    data: Transitions
    model: MLPDynamics | None
    interaction: float
    wall: float
    progress: Progress | None

    def episode(self, kind: str, index: int) -> Episode:
        """Reset the world and run one collection or evaluation episode."""
        traj = self.trajectories[index % len(self.trajectories)]
        rng = np.random.default_rng([self.spec.seed, int(self.spec.prior),
                                     0 if kind == "collect" else 1, index])
        self.world.reset(rng)
        cost = TaskCost(traj.stages, self.observer.layout, self.config.cost)
        policy = LearningPolicy(cost, self.config.mpc(), traj if self.spec.prior else None,
                                stage_orientations(traj), self.model,
                                anchor_handle=traj.handle_start)
        steps = min(self.config.rollout.max_steps, len(traj.waypoints) + self.config.extra_steps)
        rollout = replace(self.config.rollout, max_steps=steps)
        return run_episode(self.world, self.observer, policy, cost, rollout, rng)

    def iteration(self, iteration: int) -> dict[str, Any]:
        """Collect, train, evaluate; the iteration's record (``final`` set when it ends the run)."""
        started, cfg, spec = time.perf_counter(), self.config, self.spec
        collected = []
        for e in range(cfg.episodes_per_iteration):
            episode = self.episode("collect", iteration * cfg.episodes_per_iteration + e)
            collected.append(episode)
            self.interaction += episode.sim_time_s
            self.data = self.data.concat(Transitions.from_rollout(episode.obs, episode.actions))
            if self.progress is not None:
                self.progress(spec, iteration, "collect", episode)
        record: dict[str, Any] = {
            "task": spec.task, "prior": spec.prior, "seed": spec.seed, "iteration": iteration,
            "transitions": len(self.data),
            "collect_success": float(np.mean([e.success for e in collected]))}
        try:
            self.model, report = _train(self.model, self.data, cfg, spec, iteration,
                                        self.observer.layout.dim)
        except DivergedError as exc:
            self.wall += time.perf_counter() - started
            record.update(final=True, converged=False, stopped=f"diverged: {exc}",
                          interaction_s=self.interaction, wall_s=self.wall)
            return record
        evals = []
        for j in range(cfg.eval_episodes):
            evals.append(self.episode("eval", j))
            if self.progress is not None:
                self.progress(spec, iteration, "eval", evals[-1])
        success = float(np.mean([e.success for e in evals]))
        self.wall += time.perf_counter() - started
        record.update(interaction_s=self.interaction, wall_s=self.wall,
                      loss=float(report.losses[-1]),
                      held_out_loss=(float(report.held_out_losses[-1])
                                     if len(report.held_out_losses) else None),
                      eval_success=success, eval_reasons=[e.reason for e in evals])
        converged = success >= cfg.converged_success
        if converged or self.interaction >= cfg.time_limit_s:
            record.update(final=True, converged=converged,
                          stopped="converged" if converged else "time limit")
        return record


def run_learning(spec: RunSpec, config: LearnConfig, trajectories: list[ZeroShotTrajectory],
                 make_world: WorldFactory, out: Path,
                 progress: Progress | None = None) -> list[dict[str, Any]]:
    """Run (or continue) one learning run; returns its iteration records.

    Args:
        spec: task, prior, seed.
        config: the run's parameters.
        trajectories: the task's zero-shot runs (their value maps are the task cost in both
            arms; "with prior" samples around them, one per episode in turn).
        make_world: the world and observer of the task.
        out: the output root.
        progress: called after every episode.

    Raises:
        ConfigError: no zero-shot trajectory of the task.
    """
    trajectories = [t for t in trajectories if t.task == spec.task]
    if not trajectories:
        raise ConfigError(f"no zero-shot trajectory of task {spec.task!r}: the task cost is "
                          "the zero-shot programs' value maps, record them first")
    folder = spec.folder(out)
    folder.mkdir(parents=True, exist_ok=True)
    log_path, data_path, model_path = (folder / "iterations.jsonl", folder / "transitions.npz",
                                       folder / "model.npz")
    records = _read_lines(log_path)
    if records and records[-1].get("final"):
        return records
    world, observer = make_world(spec.task)
    resumed = bool(records) and data_path.exists() and model_path.exists()
    run = _Run(spec, config, trajectories, world, observer,
               Transitions.load(data_path) if resumed else Transitions.empty(
                   observer.layout.dim, 4),
               MLPDynamics.from_file(model_path) if resumed else None,
               float(records[-1]["interaction_s"]) if resumed else 0.0,
               float(records[-1]["wall_s"]) if resumed else 0.0, progress)
    if not resumed:
        records = []
        log_path.unlink(missing_ok=True)
    while True:
        record = run.iteration(len(records))
        if run.model is not None:  # the files always match the last line written
            run.model.save(model_path)
        run.data.save(data_path)
        _append(log_path, record)
        records.append(record)
        if record.get("final"):
            return records


def _train(model: MLPDynamics | None, data: Transitions, config: LearnConfig, spec: RunSpec,
           iteration: int, obs_dim: int) -> tuple[MLPDynamics, Any]:
    """Train (a new model the first time) on all transitions, 10% held out."""
    rng = np.random.default_rng([spec.seed, int(spec.prior), 2, iteration])
    fresh = model is None
    if model is None:
        model = MLPDynamics(obs_dim, 4, config.mlp, rng)
    fit, held = data.split(0.1, rng) if len(data) >= 20 else (data, None)
    report = train(model, fit, rng, config.epochs_per_iteration, held_out=held,
                   fit_normaliser=fresh or iteration < 3)
    return model, report


def _append(path: Path, record: dict[str, Any]) -> None:
    with path.open("a") as fh:
        fh.write(json.dumps(record) + "\n")


def config_record(config: LearnConfig) -> dict[str, Any]:
    """The configuration as plain values (for the run's manifest)."""
    return asdict(config)


__all__ = ["LearnConfig", "RunSpec", "config_record", "run_learning"]
