"""The language model programs (paper Sec. 4, App. A.6): one prompt file + one line each.

==================  =========  ==============================================================
LMP                 role       its code …
==================  =========  ==============================================================
planner             planner    calls ``composer("<sub-task>")`` once per sub-task
composer            composer   calls the map LMPs and ``execute(movable, ..._map=...)``
parse_query_obj     object     sets ``ret_val`` to ``detect(...)``'s object (or a computation)
get_affordance_map  map        sets ``ret_val`` to an affordance map (high = go here)
get_avoidance_map   map        … an avoidance map (high = stay away)
get_rotation_map    map        … a rotation map (quaternion x, y, z, w per voxel)
get_velocity_map    map        … a velocity-scale map (1 = default speed)
get_gripper_map     map        … a gripper map (1 closed, 0 open)
==================  =========  ==============================================================
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final, Literal

from voxposer.errors import ConfigError
from voxposer.lmp.prompt_tags import TASK_NAMES
from voxposer.lmp.sandbox import SandboxConfig

Role = Literal["planner", "composer", "object", "map"]


@dataclass(frozen=True)
class LMPSpec:
    """How one LMP is called and what its code must produce.

    Attributes:
        name: the LMP's name; also its prompt file ``prompts/<name>.txt`` and the function name
            other LMPs' code calls it by.
        role: see the module table.
        map_kind: for map LMPs, the value-map kind ("affordance"…).
        with_objects: prefix the query with ``objects = [...]`` (the scene's object names).
    """

    name: str
    role: Role
    map_kind: str | None = None
    with_objects: bool = False

    @property
    def result_name(self) -> str | None:
        """The variable the code must assign (None: the code acts through calls)."""
        return "ret_val" if self.role in ("object", "map") else None


LMP_SPECS: Final[dict[str, LMPSpec]] = {
    spec.name: spec
    for spec in (
        LMPSpec("planner", "planner", with_objects=True),
        LMPSpec("composer", "composer"),
        LMPSpec("parse_query_obj", "object", with_objects=True),
        LMPSpec("get_affordance_map", "map", "affordance"),
        LMPSpec("get_avoidance_map", "map", "avoidance"),
        LMPSpec("get_rotation_map", "map", "rotation"),
        LMPSpec("get_velocity_map", "map", "velocity"),
        LMPSpec("get_gripper_map", "map", "gripper"),
    )
}
MAP_LMPS: Final = tuple(n for n, s in LMP_SPECS.items() if s.role == "map")


@dataclass(frozen=True)
class LMPConfig:
    """Settings shared by all LMPs of a runtime.

    Attributes:
        max_attempts: LLM calls per (LMP, query) including self-correction retries (>= 1).
        temperature: sampling temperature (0 = greedy).
        max_tokens: generation limit per call [tokens].
        stop: stop sequences passed to the backend.
        max_depth: deepest nesting of LMP calls (composer → map → parse_query_obj is 3).
        prompt_dir: directory with the prompt files (None: the packaged prompts).
        sandbox: limits of each execution of generated code.
        held_out_task: a benchmark task whose few-shot examples are removed from every prompt
            (its "unseen instruction" fold, :mod:`voxposer.lmp.prompt_tags`); None keeps all.
        clause_checklist: ask the planner once more when its sub-tasks leave out a clause of
            the instruction (:mod:`voxposer.lmp.checklist`).
        intent_checklist: ask the planner once more when its post-conditions leave a
            constraint of a sub-task unmeasured (:mod:`voxposer.lmp.intent_checklist`).
        lift_after_grasp: a plan whose last sub-task grasps a free object gets
            ``composer('back to default pose')`` appended, so the object leaves the table
            (:mod:`voxposer.lmp.plan_completion`).
        grasp_before_drop: a plan sub-task that drops a free object no earlier sub-task
            grasped becomes the examples' grasp, lift, carry and release
            (:func:`~voxposer.lmp.plan_completion.grasp_before_drop`).
        carry_stay_on: the instruction's "staying on the <side> of the <object>", carried by
            no sub-task, is given to the plan's one motion
            (:func:`~voxposer.lmp.plan_completion.carry_stay_on`).
        carry_stated_constraints: a hand motion whose post-condition keeps a distance from
            an object or a speed near it, and whose words do not, gets the words
            (:func:`~voxposer.lmp.plan_carry.carry_stated_constraints`).
        fold_avoided: a sub-task that moves to or around the object the instruction only asks
            to keep away from is dropped and the avoidance said in the plan's pushes or motions
            (:func:`~voxposer.lmp.plan_avoid.fold_avoided`).
        named_places_only: a sub-task's table place the instruction does not name becomes the
            one it names, and a motion then said twice is said once
            (:func:`~voxposer.lmp.plan_places.named_places_only`).
        zone_not_destination: a motion to the table part the instruction says a speed in is
            dropped and the speed said in the motion to its place
            (:func:`~voxposer.lmp.plan_zone.zone_not_destination`).
        speed_near_folded: sub-tasks that say the instruction's speed near an object with no
            motion of their own are dropped and the speed said in the hand's one motion
            (:func:`~voxposer.lmp.plan_speed_near.speed_near_folded`).
        push_along_ends: a one-sub-task push of a block along a line becomes the examples'
            pushes to the line's near end, then its far end
            (:func:`~voxposer.lmp.plan_along.push_along_ends`).
        drop_final_reset: a final "back to default pose" after a motion of the hand to a
            place is dropped (:func:`~voxposer.lmp.plan_completion.drop_final_reset`).
        hover_over: a sub-task that makes an object hover, when the instruction hovers over
            it, becomes the hand's motion "move to a point <n>cm above the <object>"
            (:func:`~voxposer.lmp.plan_completion.hover_over`).
        correct_speed_direction: a velocity map whose set scales all go the other way than
            its query's words ("faster" written as 0.5) gets the words' factor there
            (:func:`~voxposer.lmp.checks.corrected_speed`, a ``speed_corrected`` event).
        whole_descriptions: a ``parse_query_obj`` description cut short by the program
            calling it ("third block" in "the left of the third block from the right") gets
            the relational tail back (:mod:`voxposer.lmp.descriptions`).
        object_stand_in: a ``parse_query_obj`` query naming a coloured object the scene
            lacks is asked for the one scene object of that kind the calling query names
            (:meth:`~voxposer.lmp.query_forms.QueryForms.stand_in`).
        keep_instruction_speed: a sub-task whose speed asks the opposite of the
            instruction's ("faster" planned for "a quarter of the speed") gets the
            instruction's speed phrase (:func:`~voxposer.lmp.plan_conditions.keep_instruction_speed`).
        derived_conditions: each sub-task's post-conditions are completed from its words
            (the side passed, the pushed object moved, a release, a speed, a distance kept:
            :func:`~voxposer.lmp.plan_conditions.derive_conditions`).
        resolve_exact_names: a ``parse_query_obj`` query that names a scene object exactly
            (after the synonym table) is answered ``ret_val = detect(<name>)`` without the
            model, recorded as a ``resolved`` transcript event.
        ground_references: an object the instruction names by its relation ("the leftmost
            block", "the block nearest the robot") is replaced by its scene name before the
            planner reads it (:mod:`voxposer.lmp.references`), recorded as a
            ``reference_grounded`` transcript event.
        plain_quantities: a distance the instruction says in words, other units or body
            measures ("two inches", "a hand's width") is said in centimetres before the
            planner reads it (:mod:`voxposer.lmp.quantities`), recorded as a
            ``quantity_said_plainly`` transcript event.
        retrieved_examples: how many examples of an LMP's example bank, the nearest to the
            query, follow its fixed examples (:mod:`voxposer.lmp.retrieval`; 0: none).
        batch_map_calls: the value-map LMP calls a composer program makes with literal queries
            are asked of the backend together before it runs (:mod:`voxposer.lmp.prefetch`;
            the same programs, decoded in one batch where the backend can). Off by default:
            with the default model on 2 cores it measured no faster (warm latency suite, one
            machine: 38.0 s against 36.6 s median per one-sub-task instruction, peak memory
            4.0 GB against 2.7 GB); an endpoint answers the requests concurrently.
    """

    max_attempts: int = 3
    temperature: float = 0.0
    max_tokens: int = 512
    stop: tuple[str, ...] = ()
    max_depth: int = 6
    prompt_dir: str | None = None
    sandbox: SandboxConfig = field(default_factory=SandboxConfig)
    held_out_task: str | None = None
    clause_checklist: bool = True
    intent_checklist: bool = True
    lift_after_grasp: bool = True
    grasp_before_drop: bool = True
    carry_stay_on: bool = True
    carry_stated_constraints: bool = True
    fold_avoided: bool = True
    named_places_only: bool = True
    zone_not_destination: bool = True
    speed_near_folded: bool = True
    push_along_ends: bool = True
    drop_final_reset: bool = True
    hover_over: bool = True
    correct_speed_direction: bool = True
    whole_descriptions: bool = True
    object_stand_in: bool = True
    keep_instruction_speed: bool = True
    derived_conditions: bool = True
    resolve_exact_names: bool = True
    ground_references: bool = True
    plain_quantities: bool = True
    retrieved_examples: int = 2
    batch_map_calls: bool = False

    def __post_init__(self) -> None:
        if self.held_out_task is not None and self.held_out_task not in TASK_NAMES:
            raise ConfigError(f"LMPConfig.held_out_task must be a benchmark task or None; got "
                              f"{self.held_out_task!r}; tasks are: {', '.join(TASK_NAMES)}")
        if not (isinstance(self.retrieved_examples, int) and 0 <= self.retrieved_examples <= 8):
            raise ConfigError(f"LMPConfig.retrieved_examples must be an int in [0, 8]; got "
                              f"{self.retrieved_examples!r}")
        if not (isinstance(self.max_attempts, int) and 1 <= self.max_attempts <= 10):
            raise ConfigError(f"LMPConfig.max_attempts must be an int in [1, 10]; got "
                              f"{self.max_attempts!r}")
        if not (isinstance(self.temperature, int | float) and 0.0 <= self.temperature <= 2.0):
            raise ConfigError(f"LMPConfig.temperature must be in [0, 2]; got {self.temperature!r}")
        if not (isinstance(self.max_tokens, int) and 16 <= self.max_tokens <= 8192):
            raise ConfigError(f"LMPConfig.max_tokens must be an int in [16, 8192]; got "
                              f"{self.max_tokens!r}")
        if not (isinstance(self.max_depth, int) and 1 <= self.max_depth <= 20):
            raise ConfigError(f"LMPConfig.max_depth must be an int in [1, 20]; got "
                              f"{self.max_depth!r}")


def get_spec(name: str) -> LMPSpec:
    """The spec of LMP ``name``; raises ConfigError listing the known LMPs."""
    if name not in LMP_SPECS:
        raise ConfigError(f"unknown LMP {name!r}; LMPs are: {', '.join(LMP_SPECS)}")
    return LMP_SPECS[name]
