"""Plan coverage of reworded instructions: does the planner keep each phrasing's clauses?

For every task and each of its dev (or test) phrasings (``voxposer.bench.paraphrases``), with
seen attributes drawn from a fixed seed, the planner LMP alone is asked once — nothing executes —
and its ``composer(...)`` sub-tasks are read. A plan *carries* the instruction when the clause
the task is about stays with the motion it constrains (``CARRIED``): the constraint of a
"while …" task in the same sub-task as the destination, a drop planned as grasp … release, a
push along a line to the line's near end and then its far end. Tasks without such a clause
count as carried. It is the plan-level part of the paraphrase split (a few minutes, no
rollouts); whether the maps and the executor then do it is what ``voxposer bench
--instructions paraphrased`` measures.

    python benchmarks/planner_paraphrases.py [--split dev|test] [--retrieved K] [--tasks a,b]

The planner sees the same request as in a run (the fixed examples, then the ``--retrieved`` bank
examples nearest to the instruction); the backend is ``LLMConfig.from_env()``. The last line is
machine-readable.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable

import numpy as np
from rich.console import Console
from rich.table import Table

from voxposer.bench.paraphrases import paraphrase, phrasings
from voxposer.bench.tasks import TASKS
from voxposer.lmp.backends import LLMConfig, LLMRequest, make_backend
from voxposer.lmp.checklist import planned_subtasks
from voxposer.lmp.codetext import extract_code
from voxposer.lmp.prompt import load_prompt
from voxposer.lmp.registry import LMP_SPECS, LMPConfig
from voxposer.lmp.runtime import query_message

OBJECTS = ("table", "cabinet", "top drawer", "top drawer handle", "middle drawer",
           "middle drawer handle", "bottom drawer", "bottom drawer handle", "gripper",
           "blue block", "green block", "yellow block", "pink block", "brown block", "blue line",
           "green line", "yellow line", "pink line", "brown line")
SPEED = ("speed", "slow", "fast", "quarter")


def _place(attrs: dict[str, str], key: str) -> str:
    return attrs[key].split(" of the table")[0]


def _colour(attrs: dict[str, str], key: str) -> str:
    return attrs[key].split()[0]


def _one(subtasks: list[str], *needles: str | tuple[str, ...]) -> bool:
    """Some sub-task holds every needle (a tuple: any of its words)."""
    def has(s: str, n: str | tuple[str, ...]) -> bool:
        return any(w in s for w in n) if isinstance(n, tuple) else n in s
    return any(all(has(s, n) for n in needles) for s in subtasks)


#: task → whether its plan (lower-case sub-tasks) carries the task's clause, given attributes.
CARRIED: dict[str, Callable[[dict[str, str], list[str]], bool]] = {
    "move_to_pos_staying_on_preposition": lambda a, s: _one(
        s, _colour(a, "obj"), _place(a, "pos"), ("stay", "keep", "pass")),
    "move_to_pos_velocity_near_obj": lambda a, s: _one(
        s, _colour(a, "obj"), a["dist"], SPEED, _place(a, "pos")),
    "move_to_pos_velocity_in_region": lambda a, s: _one(
        s, _place(a, "region"), SPEED, _place(a, "pos")),
    "move_to_pos_min_distance": lambda a, s: _one(
        s, _colour(a, "obj"), a["dist"], _place(a, "pos")),
    "push_to_pos_avoid_obstacle": lambda a, s: _one(
        s, _colour(a, "obj"), _colour(a, "obstacle"), "push"),
    "grasp_at_velocity": lambda a, s: _one(s, "grasp", SPEED),
    "drop_to_pos": lambda a, s: _one(s, "grasp") and _one(s, "release"),
    "push_along_line": lambda a, s: _one(s, "near end") and _one(s, "far end"),
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--split", choices=("dev", "test"), default="dev")
    parser.add_argument("--retrieved", type=int, default=LMPConfig().retrieved_examples,
                        help="bank examples chosen per instruction (default: LMPConfig's)")
    parser.add_argument("--tasks", default="all", help="comma-separated task names or 'all'")
    parser.add_argument("--seed", type=int, default=1000, help="first attribute seed")
    args = parser.parse_args()
    tasks = list(TASKS) if args.tasks == "all" else args.tasks.split(",")
    prompt = load_prompt("planner")
    backend = make_backend(LLMConfig.from_env())
    console = Console()
    table = Table("task", "carried", "plans that drop the clause")
    carried = total = 0
    start = time.perf_counter()
    for task in tasks:
        misses, n = [], len(phrasings(task, args.split))
        for i in range(n):
            attrs = TASKS[task].sample_attributes(np.random.default_rng(args.seed + i), "seen")
            instruction = paraphrase(task, attrs, args.split, i)
            messages = prompt.messages(query_message(LMP_SPECS["planner"], instruction, OBJECTS),
                                       retrieved=args.retrieved)
            extra = len(messages) - 1 > prompt.n_prefix_messages
            request = LLMRequest(messages=messages, max_tokens=256, prefix_id=prompt.prefix_id,
                                 prefix_messages=prompt.n_prefix_messages if extra else None)
            code = extract_code(backend.complete(request).text)
            subtasks = [s.lower() for s in planned_subtasks(code) or []]
            if CARRIED.get(task, lambda a, s: True)(attrs, subtasks):
                carried += 1
            else:
                misses.append(f"{instruction!r} -> {' ; '.join(subtasks) or code.strip()!r}")
        total += n
        table.add_row(task, f"{n - len(misses)}/{n}", "\n".join(misses))
    seconds = time.perf_counter() - start
    backend.close()
    console.print(table)
    print(f"split={args.split} retrieved={args.retrieved} plans={total} carried={carried} "
          f"carried_pct={100 * carried / max(total, 1):.1f} "
          f"seconds_per_plan={seconds / max(total, 1):.2f}")


if __name__ == "__main__":
    main()
