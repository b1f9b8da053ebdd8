"""Dynamics models: of pushed objects (:class:`DynamicsModel`, used by the push MPC) and of
state vectors (:class:`StateDynamicsModel`, used by the waypoint MPC; learned:
:class:`MLPDynamics`)."""

from voxposer.planning.dynamics.linear import LinearDynamics
from voxposer.planning.dynamics.mlp import MLPConfig, MLPDynamics, Normaliser
from voxposer.planning.dynamics.model import DynamicsModel, PushBatch, PushPrediction
from voxposer.planning.dynamics.state_model import StateDynamicsModel
from voxposer.planning.dynamics.training import TrainReport, Transitions, train
from voxposer.planning.dynamics.translation import TranslationPush, translate_points

__all__ = [
    "DynamicsModel",
    "LinearDynamics",
    "MLPConfig",
    "MLPDynamics",
    "Normaliser",
    "PushBatch",
    "PushPrediction",
    "StateDynamicsModel",
    "TrainReport",
    "Transitions",
    "TranslationPush",
    "train",
    "translate_points",
]
