"""The disturbance schedule against a fake world that records calls: each kind fires at its
fraction of sub-task progress (or its sim-time offset), at most one per replan, never within
reach of the target, on the right object, and a refused kind is retried."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from voxposer.control.disturbance_schedule import DisturbanceSchedule, Disturber
from voxposer.errors import ConfigError, LayoutError


class FakeWorld:
    """Records which disturbance method was called with what, at which sim time."""

    def __init__(self, blocks: tuple[str, ...] = ("blue block", "red block", "green block")):
        self.data = SimpleNamespace(time=0.0)
        self.step_callbacks: list[Any] = []
        self.object_names = (*blocks, "table", "top drawer", "top drawer handle")
        self.positions = {b: np.array([0.1 * k, 0.2, 0.025]) for k, b in enumerate(blocks)}
        self.gripper, self.ee = 0.0, np.array([0.0, 0.0, 0.5])
        self.calls: list[tuple[Any, ...]] = []
        self.refuse = 0

    def get_gripper_state(self) -> float:
        return self.gripper

    def gripper_opening(self) -> float:
        return 0.05 * self.gripper  # closed on a block

    def get_ee_pose(self) -> tuple[np.ndarray, np.ndarray]:
        return self.ee, np.array([0.0, 0.0, 0.0, 1.0])

    def object_position(self, name: str) -> np.ndarray:
        return self.positions.get(name, np.zeros(3))

    def _done(self, kind: str, target: str) -> Any:
        if self.refuse:
            self.refuse -= 1
            raise LayoutError("no free spot")
        return SimpleNamespace(target=target, before=np.zeros(3), after=np.ones(3),
                               duration=0.0)

    def push_robot(self, rng: np.random.Generator) -> Any:
        self.calls.append(("push_robot", self.data.time))
        return self._done("force", "panda_link5")

    def displace_object(self, rng: np.random.Generator, name: str | None = None) -> Any:
        self.calls.append(("displace_object", name, self.data.time))
        return self._done("displace", str(name))

    def pull_drawer(self, rng: np.random.Generator, drawer: str | None = None) -> Any:
        self.calls.append(("pull_drawer", drawer, self.data.time))
        return self._done("revert", str(drawer))

    def return_object(self, rng: np.random.Generator, name: str, to: Any) -> Any:
        self.calls.append(("return_object", name, tuple(np.round(to, 3)), self.data.time))
        return self._done("revert", name)


def _replan(disturber: Disturber, result: SimpleNamespace, covered: float, d0: float = 0.5,
            remaining: float | None = None) -> None:
    """One replan of ``result``'s sub-task, ``covered`` metres along x from (0, 0, 0.5)."""
    result.replans += 1
    result.final_distance = d0 - covered if remaining is None else remaining
    disturber.world.data.time += 0.2
    plan = SimpleNamespace(cost_map=SimpleNamespace(start=np.array([covered, 0.0, 0.5])))
    disturber.on_replan(result, plan)


def _subtask(entity: str) -> SimpleNamespace:
    return SimpleNamespace(entity=entity, replans=0, final_distance=float("inf"))


def _kinds(world: FakeWorld) -> list[str]:
    return [c[0] for c in world.calls]


def test_each_kind_fires_at_its_fraction_of_progress() -> None:
    world = FakeWorld()
    disturber = Disturber(world, np.random.default_rng(0), relevant=("red block",))
    hand = _subtask("gripper")
    _replan(disturber, hand, 0.0)
    _replan(disturber, hand, 0.09)  # p = 0.18
    assert world.calls == []
    _replan(disturber, hand, 0.10)  # p = 0.2
    assert _kinds(world) == ["push_robot"]
    _replan(disturber, hand, 0.25)  # p = 0.5: the revert (0.4) needs an object entity
    _replan(disturber, hand, 0.29)
    assert _kinds(world) == ["push_robot"]
    _replan(disturber, hand, 0.30)  # p = 0.6: a gripper sub-task displaces the named block
    assert world.calls[-1][:2] == ("displace_object", "red block")
    assert [d["progress"] for d in disturber.applied] == [0.2, 0.6]
    drawer = _subtask("top drawer handle")  # the next sub-task: the revert, at its own 0.4
    _replan(disturber, drawer, 0.0)
    _replan(disturber, drawer, 0.15)
    assert len(world.calls) == 2
    _replan(disturber, drawer, 0.2)
    assert world.calls[-1][:2] == ("pull_drawer", "top drawer")
    assert [d["kind"] for d in disturber.applied] == ["push_robot", "displace_object",
                                                      "revert_progress"]
    _replan(disturber, drawer, 0.5, remaining=0.1)
    assert len(world.calls) == 3  # each kind once per episode


def test_one_kind_per_replan_and_none_within_reach() -> None:
    world = FakeWorld()
    disturber = Disturber(world, np.random.default_rng(0))
    block = _subtask("blue block")
    _replan(disturber, block, 0.0)
    _replan(disturber, block, 0.49, remaining=0.01)  # p = 0.98 but within 2 cm: quiet
    assert world.calls == []
    for _ in range(3):
        _replan(disturber, block, 0.45)
    # push, then the revert (0.4: back to where the sub-task started), then the entity moved
    assert world.calls[0][0] == "push_robot"
    assert world.calls[1][:3] == ("return_object", "blue block", (0.0, 0.0, 0.5))
    assert world.calls[2][:2] == ("displace_object", "blue block")
    assert len({c[-1] for c in world.calls}) == 3  # three different replans


def test_a_held_block_is_left_alone_and_a_refusal_is_retried() -> None:
    world = FakeWorld()
    world.gripper, world.ee = 1.0, world.positions["blue block"] + [0.0, 0.0, 0.02]
    disturber = Disturber(world, np.random.default_rng(0), relevant=("blue block",),
                          schedule=DisturbanceSchedule(progress=(0.9, 0.1, 0.9)))
    carried = _subtask("blue block")
    _replan(disturber, carried, 0.0)
    world.refuse = 1
    _replan(disturber, carried, 0.1)  # displacement due, but the world refuses: pending
    assert disturber.applied == []
    _replan(disturber, carried, 0.1)
    (call,) = world.calls[1:]
    assert call[0] == "displace_object" and call[1] in ("red block", "green block")


def test_the_sim_time_schedule_fires_at_its_offsets() -> None:
    world = FakeWorld()
    disturber = Disturber(world, np.random.default_rng(0), entity="green block")
    with disturber.attach():
        for k in range(40):  # 4 s of 0.1 s steps, the first at t = 0.5 s
            world.data.time = round(0.5 + 0.1 * k, 3)
            for callback in list(world.step_callbacks):
                callback(world)
    assert world.step_callbacks == []
    assert [(c[0], c[-1]) for c in world.calls] == [("push_robot", 1.5),
                                                    ("return_object", 2.5),
                                                    ("displace_object", 3.5)]
    assert world.calls[1][1:3] == ("green block", (0.2, 0.2, 0.025))
    assert all(d["progress"] is None for d in disturber.applied)


def test_schedule_values_are_checked() -> None:
    with pytest.raises(ConfigError, match="progress"):
        DisturbanceSchedule(progress=(0.2, 0.4))  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="<= 1"):
        DisturbanceSchedule(progress=(0.2, 0.4, 1.5))
