"""Objects and table places named by relation: how often the grounding names the episode's own.

On the ``--instructions vague-relational`` split's scenes (``reset_episode`` of each task, the
split's instruction rendered from the reset layout, :mod:`voxposer.bench.vague_relational`),
every instruction that names its block ([obj]) or its region ([region]) by a relation is
grounded (:func:`voxposer.lmp.references.grounded_instruction`) on the perceived scene, as
``voxposer run`` does before the planner reads it. Counted: phrases grounded, grounded to the
episode's own object or place, grounded to another (wrong), left to the model (a tie, an unseen
candidate, a form the grammar does not read). No language model is run. Dev seeds use the
split's dev words, test seeds its test words. The last line is machine-readable.

    MUJOCO_GL=egl python benchmarks/grounding.py [--seeds dev|test] [--episodes 6]
        [--perception ground-truth|colour-depth-noisy]
"""

from __future__ import annotations

import argparse
import os
from collections import Counter

os.environ.setdefault("MUJOCO_GL", "egl")

from rich.console import Console
from rich.progress import track

from voxposer.bench.protocol import SEED_SETS
from voxposer.bench.suites import TASKS_SUITE, suite_task
from voxposer.bench.task import reset_episode
from voxposer.bench.vague_relational import render, scene_blocks
from voxposer.envs import TabletopWorld
from voxposer.lmp.prompt_tags import TASK_NAMES
from voxposer.lmp.references import grounded_instruction
from voxposer.lmp.scene import RobotScene
from voxposer.lmp.transcript import Transcript
from voxposer.pipeline import simulated_perceiver


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", choices=("dev", "test"), default="dev")
    ap.add_argument("--episodes", type=int, default=6, help="seeds per task (from the set's first)")
    ap.add_argument("--perception", choices=("ground-truth", "colour-depth-noisy"),
                    default="ground-truth")
    args = ap.parse_args()
    first = SEED_SETS[args.seeds].first
    world, console, counts = TabletopWorld(), Console(), Counter()
    jobs = [(seed, task) for seed in range(first, first + args.episodes) for task in TASK_NAMES]
    for seed, task in track(jobs, description="grounding", console=console):
        setup = reset_episode(suite_task(TASKS_SUITE, task), world, "seen", seed)
        rendered = render(task, setup.attributes, *scene_blocks(world), args.seeds, seed)
        slots = [s for s in ("obj", "region") if s in rendered.vague_slots]
        if not slots:
            continue
        scene = RobotScene(simulated_perceiver(world, args.perception, seed=seed), world)
        transcript = Transcript()
        grounded_instruction(rendered.instruction, scene, transcript)
        names = [e["name"] for e in transcript.events if e["event"] == "reference_grounded"]
        for slot in slots:
            counts["phrases"] += 1
            meant = setup.attributes[slot]
            if meant in names:
                counts["right"] += 1
            elif names:
                counts["wrong"] += 1
                console.print(f"wrong: {task} seed {seed}: {rendered.instruction!r} → {names}, "
                              f"meant {meant}")
            else:
                counts["left"] += 1
                console.print(f"left to the model: {task} seed {seed}: {rendered.instruction!r}")
    n = max(counts["phrases"], 1)
    console.print(f"{counts['phrases']} relational phrases ({args.seeds} seeds, {args.perception}): "
                  f"{counts['right']} grounded to the episode's own, {counts['wrong']} to another, "
                  f"{counts['left']} left to the model")
    print(f"seeds={args.seeds} perception={args.perception} phrases={counts['phrases']} "
          f"right={counts['right']} wrong={counts['wrong']} left={counts['left']} "
          f"right_rate={counts['right'] / n:.3f}")


if __name__ == "__main__":
    main()
