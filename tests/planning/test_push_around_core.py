"""A block pushed around another's avoidance core in the MuJoCo world keeps moving (reference
programs, exact perception, no LLM)."""

from voxposer.bench import run_episode
from voxposer.bench.episode import EpisodeJob


def test_a_push_along_the_edge_of_an_avoidance_core_does_not_stall(world) -> None:
    """Dev seed 13 of "push the [obj] to the [pos] while staying away from [obstacle]": the
    green block's path bent around the brown block's 10 cm avoidance core with its centre on
    the core's edge. The MPC counted the predicted outline against the planner's obstacles,
    which hold that core: every push along the path put half the block in it, 1 cm nudges
    scored best and the block stalled 29 cm from the right side of the table. The outline is
    now checked against the scene's objects, the centre against the planner's obstacles."""
    record = run_episode(EpisodeJob("push_to_pos_avoid_obstacle", "seen", 13, llm="reference"),
                         world)
    assert record.error is None, record.error
    assert record.success, record.reason
    assert record.metrics["closest"] >= 0.09 and record.metrics["obstacle_moved"] < 0.02
