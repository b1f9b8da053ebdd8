"""Episodes on noisy pixels that used to fail on the pixel perception's hard cases."""

from __future__ import annotations

from voxposer.bench.episode import EpisodeJob, run_episode


def test_a_gray_block_closed_on_by_the_gray_gripper_is_still_seen(world) -> None:
    # the gripper's fingers reach the gray block: one gray cluster; the block is tracked
    rec = run_episode(EpisodeJob("drop_to_pos", "unseen", 1, seed_set="dev",
                                 perception="colour-depth-noisy"), world)
    assert "no camera sees it" not in (rec.program_error or "")
    assert rec.success, rec.reason
