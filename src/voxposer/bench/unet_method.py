"""The "U-Net + MP" baseline (paper Table 2 and App. A.4, after Sharma et al. [50]) as a
benchmark method: a trained U-Net's cost map steers the same planner and executor as VoxPoser.

At every replan of the closed-loop executor (:class:`~voxposer.control.ClosedLoopController`,
5 Hz) the fused point cloud is voxelised onto the planning grid, the U-Net predicts the cost for
the episode's instruction (:func:`voxposer.unet.predict.predict_cost_map`) and the planner
searches that cost (:meth:`~voxposer.planning.PathPlanner.plan_on_cost`) — no value map is
composed and no LLM runs. The entity is what the task's plan moves first:

* the **end effector**: the hand follows the predicted-cost path, replanned at every step;
* an **object or a part** (a block, a drawer handle): the predicted map is the object's cost —
  its target the lowest predicted cost in the object's layer on the table — and the pushing
  loop's random-shooting MPC over the heuristic push dynamics pushes it along that cost.

What to move, and whether the first sub-task is a grasp, are not the U-Net's to say: they are
read from the task's reference plan (:func:`first_subtask`), never its maps. The training target
(:mod:`voxposer.bench.unet_data`) is the cost of that **first sub-task only**, so the U-Net
predicts one cost map per instruction and only the first sub-task runs on it; a grasp closes the
gripper at the predicted target (a gripper map closed there only, so the planner approaches top
down). Later sub-tasks of the plan: "back to default pose" (a fixed motion, no cost map) runs;
the first other one (drop_to_pos's carry and release, push_along_line's second push) is not
run — the method raises :class:`~voxposer.errors.ExecutionFailedError` saying so, and the task's
check judges the state reached.

The checkpoint is loaded once per worker process (cached by path and modification time);
episodes record its path and sha256 prefix (:func:`checkpoint_identity`).
"""

from __future__ import annotations

import functools
import hashlib
import re
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from voxposer.errors import ConfigError, ExecutionFailedError
from voxposer.geometry.frames import TOP_DOWN_QUAT
from voxposer.planning.planner import PathPlanner, Plan

if TYPE_CHECKING:
    from voxposer.bench.programs import Programs
    from voxposer.bench.task import EpisodeSetup
    from voxposer.control.config import ExecutorConfig
    from voxposer.geometry.voxel_grid import VoxelGrid
    from voxposer.perception.point_cloud import PointCloud
    from voxposer.planning.planner_config import PlannerConfig
    from voxposer.unet.checkpoint import Checkpoint

#: the method's name (``--method``), and the ``llm`` of its records: it runs no language model.
UNET_MP: Final = "unet_mp"
NO_LLM: Final = "none"
#: the reference plans' fixed motion after a sub-task (no cost map: run as it is).
DEFAULT_POSE: Final = "back to default pose"
#: the instruction splits the method runs: the templates it was trained on, and the paraphrase
#: split's phrasings (words its vocabulary never saw map to its one unknown token) — its
#: "unseen instructions", as the paper's U-Net + MP is tested on instructions outside its
#: training data.
UNET_INSTRUCTIONS: Final = ("seen", "paraphrased")
#: hex digits of the checkpoint's sha256 each record keeps.
SHA_PREFIX: Final = 16
_COMPOSER = re.compile(r"composer\('([^']+)'\)")
_MOVABLE = re.compile(r"movable = parse_query_obj\('([^']+)'\)")


class FirstSubtask(NamedTuple):
    """What a task's reference plan does first (the sub-task the U-Net was trained on).

    Attributes:
        subtask: its text ("grasp the blue block").
        entity: what it moves ("gripper", "blue block", "middle drawer handle").
        grasps: it sets a gripper map (a pick): the gripper closes at the reached target.
        then: the plan's later sub-tasks, in order.
    """

    subtask: str
    entity: str
    grasps: bool
    then: tuple[str, ...]


def first_subtask(programs: Programs, instruction: str) -> FirstSubtask:
    """The first sub-task of the reference ``programs`` for ``instruction``.

    Raises:
        ConfigError: the programs plan no sub-task, or it names no movable.
    """
    subtasks = _COMPOSER.findall(programs.code("planner", instruction))
    if not subtasks:
        raise ConfigError(f"the reference plan of {instruction!r} has no sub-task")
    code = programs.code("composer", subtasks[0])
    movable = _MOVABLE.search(code)
    if movable is None:
        raise ConfigError(f"the reference sub-task {subtasks[0]!r} names no movable")
    return FirstSubtask(subtasks[0], movable.group(1), "gripper_map" in code,
                        tuple(subtasks[1:]))


def planning_grid_shape(grid: VoxelGrid, config: ExecutorConfig) -> tuple[int, ...]:
    """The planner's cost grid (X, Y, Z) [voxels]: ``grid`` coarsened as its cost maps are."""
    return grid.coarsen(config.ee_planner.cost.downsample).shape


@functools.lru_cache(maxsize=2)
def _load(path: str, mtime_ns: int, grid_shape: tuple[int, ...]) -> Checkpoint:
    from voxposer.unet.checkpoint import load_checkpoint

    return load_checkpoint(Path(path), grid_shape=grid_shape)


def load_for_grid(path: str | Path, grid_shape: tuple[int, ...]) -> Checkpoint:
    """The checkpoint at ``path`` (loaded once per process and modification), refused
    (ConfigError naming both shapes) when it predicts on another cost grid than ``grid_shape``,
    or naming the path when there is no file."""
    p = Path(path)
    if not p.is_file():
        raise ConfigError(f"no U-Net checkpoint at {p} (--unet-checkpoint)")
    return _load(str(p.resolve()), p.stat().st_mtime_ns, tuple(grid_shape))


@functools.lru_cache(maxsize=8)
def _sha256(path: str, mtime_ns: int) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def checkpoint_identity(path: str | Path) -> dict[str, str]:
    """What an episode records of the checkpoint it ran: ``{"path", "sha256"}`` (a prefix of
    :data:`SHA_PREFIX` hex digits)."""
    p = Path(path)
    return {"path": str(p), "sha256": _sha256(str(p.resolve()), p.stat().st_mtime_ns)[:SHA_PREFIX]}


def check_unet_options(method: str, llm: str, checkpoint: Path | None, *, suite: str,
                       instructions: str) -> None:
    """What a benchmark run of ``method`` needs of the U-Net options (BenchConfig's check).

    Raises:
        ConfigError: unet_mp without a checkpoint, with an LLM, another suite than "tasks" or
            instructions other than :data:`UNET_INSTRUCTIONS`; a missing file or one for
            another cost grid; a checkpoint or ``llm="none"`` with another method.
    """
    if method != UNET_MP:
        if checkpoint is not None:
            raise ConfigError(f"--unet-checkpoint is for --method {UNET_MP} only; got --method "
                              f"{method}")
        if llm == NO_LLM:
            raise ConfigError(f"llm={NO_LLM!r} is for method {UNET_MP!r} only; method {method!r} "
                              "needs reference programs or an LLM backend")
        return
    if checkpoint is None:
        raise ConfigError(f"--method {UNET_MP} needs --unet-checkpoint PATH (a model.pt written "
                          "by voxposer train-unet)")
    if llm != NO_LLM:
        raise ConfigError(f"--method {UNET_MP} runs no LLM (its cost map is the U-Net's); drop "
                          f"--llm {llm}")
    if suite != "tasks" or instructions not in UNET_INSTRUCTIONS:
        raise ConfigError(f"--method {UNET_MP} runs the 13 tasks with instructions "
                          f"{' or '.join(map(repr, UNET_INSTRUCTIONS))} (its training "
                          "instructions, or reworded ones it never saw; 'unseen' holds examples "
                          f"out of an LLM's prompts, which it has none of); got suite={suite!r}, "
                          f"instructions={instructions!r}")
    from voxposer.control.config import ExecutorConfig
    from voxposer.envs.config import WorldConfig

    load_for_grid(checkpoint, planning_grid_shape(WorldConfig().grid, ExecutorConfig()))


class PredictedCostPlanner(PathPlanner):
    """A :class:`PathPlanner` whose every plan searches the U-Net's cost for ``instruction`` in
    the latest observation's fused cloud (in colour); the value maps handed to :meth:`plan` are not read.

    Args:
        grid: the workspace grid; config: the planner parameters (its cost-map settings are
            the predicted map's, as they were the training target's).
        checkpoint: the U-Net; instruction: what it is conditioned on.
        observe_cloud: the observation: the four views' fused cloud, with colour.
        close_at_target: a grasp: the gripper map is closed at the predicted target only.
    """

    def __init__(self, grid: VoxelGrid, config: PlannerConfig, checkpoint: Checkpoint,
                 instruction: str, observe_cloud: Callable[[], PointCloud], *,
                 close_at_target: bool = False) -> None:
        super().__init__(grid, config)
        self.checkpoint, self.instruction = checkpoint, instruction
        self.observe_cloud, self.close_at_target = observe_cloud, close_at_target

    def plan(self, affordance_map: NDArray, start: ArrayLike, *,
             avoidance_map: NDArray | None = None, rotation_map: NDArray | None = None,
             velocity_map: NDArray | None = None, gripper_map: NDArray | None = None,
             occupancy: NDArray[np.bool_] | None = None,
             entity_occupancy: NDArray[np.bool_] | None = None,
             current_quat: ArrayLike = TOP_DOWN_QUAT, current_gripper: float = 0.0,
             layer_z: float | None = None, off_limits: NDArray[np.bool_] | None = None) -> Plan:
        """Plan from ``start`` [m], shape (3,), on the predicted cost (obstacles from
        ``occupancy``, the entity's own voxels, ``layer_z`` and ``off_limits`` as
        :meth:`PathPlanner.plan`)."""
        from voxposer.unet.predict import predict_cost_map

        cmap = predict_cost_map(self.checkpoint, self.observe_cloud(), self.instruction,
                                grid=self.grid, start=start, occupancy=occupancy,
                                config=self.config.cost, entity_occupancy=entity_occupancy,
                                layer_z=layer_z, off_limits=off_limits)
        closed = None
        if self.close_at_target:
            closed = np.zeros(self.grid.shape, dtype=np.float32)
            closed[tuple(cmap.fine_targets.T)] = 1.0
        return self.plan_on_cost(cmap, gripper_map=closed, current_quat=current_quat,
                                 current_gripper=current_gripper)


def run_unet_mp(world: Any, setup: EpisodeSetup, checkpoint: str | None,
                config: ExecutorConfig, rng: np.random.Generator,
                on_replan: Callable[[Any, Any], None] | None = None, *,
                push_model: Any = None) -> None:
    """Carry out ``setup.instruction`` with the U-Net's cost maps (see the module docs).

    Args:
        world: the simulated robot (the MuJoCo world).
        checkpoint: the U-Net checkpoint's path.
        config: closed-loop parameters; rng: randomness of the pushing MPC.
        on_replan: called after every replan (disturbances).
        push_model: the pushing MPC's dynamics model (None: the paper's heuristic).

    Raises:
        ConfigError: no or a wrong checkpoint.
        ExecutionFailedError: the first sub-task did not reach its target, or the plan goes on
            with a sub-task the U-Net has no cost map for.
    """
    from voxposer.bench.tasks import get_task
    from voxposer.control.closed_loop import ClosedLoopController
    from voxposer.perception.pixel_labels import colour_cloud
    from voxposer.pipeline import Embodiment

    if checkpoint is None:
        raise ConfigError(f"method {UNET_MP!r} needs a U-Net checkpoint")
    body = Embodiment.simulated(world)
    grid, perceiver = body.perceiver.grid, body.perceiver
    ckpt = load_for_grid(checkpoint, planning_grid_shape(grid, config))
    task = get_task(setup.task)  # the plan is the template's (a paraphrase reads the same)
    first = first_subtask(task.reference(setup.attributes), task.instruction(setup.attributes))
    loop = ClosedLoopController(body.robot, perceiver, rng, config)
    def observe_cloud() -> PointCloud:  # with colour, as the training data
        return colour_cloud(world.observe(rgb=True), grid)

    loop.ee_planner = PredictedCostPlanner(grid, config.ee_planner, ckpt, setup.instruction,
                                           observe_cloud, close_at_target=first.grasps)
    loop.object_planner = PredictedCostPlanner(grid, config.object_planner, ckpt,
                                               setup.instruction, observe_cloud)
    loop.on_replan = on_replan
    loop.push_model = push_model
    name = str(perceiver.detect(first.entity)["name"])
    # the executor requires an affordance map; the predicted-cost planners never read it
    unread = np.zeros(grid.shape, dtype=np.float32)
    result = loop(lambda: perceiver.detect(name), affordance_map=unread)
    if not result.success:
        raise ExecutionFailedError(first.subtask, result.reason, f"{UNET_MP}: {result.message}")
    for later in first.then:
        if later != DEFAULT_POSE:
            raise ExecutionFailedError(later, "not run", f"{UNET_MP} predicts one cost map per "
                                       "instruction, for its first sub-task (the training "
                                       "target); later sub-tasks are not run")
        body.robot.reset_to_default_pose()


__all__ = ["DEFAULT_POSE", "NO_LLM", "UNET_INSTRUCTIONS", "UNET_MP", "FirstSubtask", "PredictedCostPlanner",
           "check_unet_options", "checkpoint_identity", "first_subtask", "load_for_grid",
           "planning_grid_shape", "run_unet_mp"]
