"""Dynamics models of pushed objects, used by the MPC through :class:`DynamicsModel`."""

from voxposer.planning.dynamics.model import DynamicsModel, PushBatch, PushPrediction
from voxposer.planning.dynamics.translation import TranslationPush, translate_points

__all__ = ["DynamicsModel", "PushBatch", "PushPrediction", "TranslationPush", "translate_points"]
