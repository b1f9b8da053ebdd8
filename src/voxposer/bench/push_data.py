"""Pushing transitions from the simulator, and the learned push model trained on them.

:func:`collect_pushes` lays out random tabletop scenes (dev seeds' generator), samples pushes of
a random block exactly as the pushing MPC does (:func:`voxposer.planning.mpc.sample_pushes`, on
the block's perceived points) and plays each in a private copy of the world
(:class:`~voxposer.bench.sim_dynamics.SimulatedPush`): the transitions, in the push's frame
(:mod:`voxposer.planning.dynamics.learned_push`), that :func:`fit_push_model` trains the MLP on.
:func:`push_errors` compares a model's predictions with held-out simulated outcomes — the
learned model beside the paper's heuristic (the object translates with the push).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from voxposer.bench.sim_dynamics import SimulatedPush
from voxposer.planning.dynamics import DynamicsModel, PushBatch, TranslationPush
from voxposer.planning.dynamics.learned_push import (
    ACTION_DIM,
    STATE_DIM,
    LearnedPush,
    push_actions,
    push_outcome,
)
from voxposer.planning.dynamics.mlp import MLPConfig, MLPDynamics
from voxposer.planning.dynamics.training import Transitions, train
from voxposer.planning.mpc import sample_pushes
from voxposer.planning.push_primitive import PushConfig


def _yaw(before: NDArray[np.float64], after: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation about z [rad] taking ``before`` (P, 3) to each of ``after`` (S, P, 3) (2-D
    least squares about the centroids)."""
    a = before[:, :2] - before[:, :2].mean(axis=0)
    b = after[:, :, :2] - after[:, :, :2].mean(axis=1, keepdims=True)
    cross = np.einsum("pi,spi->s", np.column_stack([-a[:, 1], a[:, 0]]), b)
    dot = np.einsum("pi,spi->s", a, b)
    return np.arctan2(cross, dot)


def collect_pushes(world: object, n_pushes: int, rng: np.random.Generator, *,
                   per_scene: int = 16, on_scene: Callable[[int], None] | None = None
                   ) -> Transitions:
    """``n_pushes`` simulated pushes, ``per_scene`` in each random scene (see the module).

    Returns transitions with state (along, across, yaw) [m, m, rad], zero before the push,
    action (lateral, depth, distance [m], incidence [rad]); ``on_scene`` gets the pushes done so far.
    """
    from voxposer.envs import COLORS, SceneLayout
    from voxposer.pipeline import simulated_perceiver

    actions, outcomes = [], []
    done = 0
    while done < n_pushes:
        blocks = tuple(str(c) for c in rng.choice(sorted(COLORS), size=int(rng.integers(1, 4)),
                                                  replace=False))
        world.reset(rng, SceneLayout(blocks=blocks, cabinet=False))  # type: ignore[attr-defined]
        block = simulated_perceiver(world, "ground-truth").detect(f"{blocks[0]} block")
        points = np.asarray(block.points, dtype=np.float64)
        k = min(per_scene, n_pushes - done)
        pushes, _, _ = sample_pushes(points, rng, replace(PushConfig(), n_samples=k))
        centre = points.mean(axis=0)
        sim = SimulatedPush(world).predict(centre, points, pushes)
        yaw = _yaw(points, sim.points)
        actions.append(push_actions(centre, pushes, points))
        outcomes.append(np.array([push_outcome(centre, pushes.directions[i], sim.centres[i],
                                               float(yaw[i])) for i in range(k)]))
        done += k
        if on_scene is not None:
            on_scene(done)
    acts = np.concatenate(actions)
    return Transitions(np.zeros((len(acts), STATE_DIM)), acts, np.concatenate(outcomes))


def fit_push_model(transitions: Transitions, rng: np.random.Generator, *, epochs: int = 200,
                   config: MLPConfig | None = None) -> LearnedPush:
    """An MLP push model trained on ``transitions`` (L2, Adam; :func:`train`)."""
    mlp = MLPDynamics(STATE_DIM, ACTION_DIM, config or MLPConfig(hidden_sizes=(64, 64)), rng)
    train(mlp, transitions, rng, epochs)
    return LearnedPush(mlp)


def push_errors(model: DynamicsModel, transitions: Transitions) -> dict[str, float]:
    """Median and 90th-percentile error of ``model``'s predicted centre [m] and |yaw| error
    [deg] on held-out simulated pushes (each push's object: a 5 cm square turned to the push's
    recorded incidence, so the same features reach the model)."""
    acts, truth = transitions.actions, transitions.next_obs
    n = len(acts)
    pred_c, pred_yaw = np.zeros((n, 2)), np.zeros(n)
    half = 0.025
    for i in range(n):  # each push has its own square (its incidence)
        turn = -float(acts[i, 3])
        c, s = np.cos(turn), np.sin(turn)
        corners = np.array([[half, half], [-half, half], [-half, -half], [half, -half]])
        edges = np.concatenate([corners + (np.roll(corners, -1, 0) - corners) * t
                                for t in np.linspace(0, 1, 6)[:-1]])
        square = np.column_stack([edges @ np.array([[c, s], [-s, c]]), np.zeros(len(edges))])
        push = PushBatch(np.array([[acts[i, 1], acts[i, 0], 0.0]]), np.array([[1.0, 0.0, 0.0]]),
                         acts[i, 2:3])
        pred = model.predict(np.zeros(3), square, push)
        pred_c[i] = pred.centres[0, :2]
        pred_yaw[i] = _yaw(square, pred.points)[0]
    centre_err = np.linalg.norm(pred_c - truth[:, :2], axis=1)
    yaw_err = np.degrees(np.abs((pred_yaw - truth[:, 2] + np.pi) % (2 * np.pi) - np.pi))
    return {"centre_median_m": float(np.median(centre_err)),
            "centre_p90_m": float(np.percentile(centre_err, 90)),
            "yaw_median_deg": float(np.median(yaw_err)),
            "yaw_p90_deg": float(np.percentile(yaw_err, 90))}


def heuristic_errors(transitions: Transitions) -> dict[str, float]:
    """:func:`push_errors` of the paper's heuristic (:class:`TranslationPush`)."""
    return push_errors(TranslationPush(), transitions)


__all__ = ["collect_pushes", "fit_push_model", "heuristic_errors", "push_errors"]
