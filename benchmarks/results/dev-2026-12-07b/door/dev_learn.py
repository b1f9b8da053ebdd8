"""Dev probe (issue 15): one door learning run on dev seed 10 (τ₀ from the reference program on
seed 10), 180 s budget; arms chosen by argv: offset σ [m] and whether held stages score the
handle. Writes under /work/runs/door/<name>/."""
import sys
from dataclasses import replace
from pathlib import Path
from voxposer.cli.learn_progress import make_world
from voxposer.learning.loop import LearnConfig, RunSpec, run_learning
from voxposer.learning.record import record_zero_shot
from voxposer.learning.reference import INSTRUCTIONS, reference_backend
from voxposer.learning.task_cost import TaskCostConfig

name, offset, at_handle = sys.argv[1], float(sys.argv[2]), sys.argv[3] == "1"
seed = int(sys.argv[4]) if len(sys.argv) > 4 else 10
world, _ = make_world("door")
traj = record_zero_shot(world, reference_backend("door"), INSTRUCTIONS["door"], task="door",
                        source="reference", seed=seed, period_s=0.25)
print("tau0", traj.success, len(traj.waypoints), flush=True)
rel = len(sys.argv) > 5 and sys.argv[5] == "rel"
cfg = LearnConfig(episode_offset_m=offset, relative_prior=rel, cost=TaskCostConfig(held_at_handle=at_handle))
def progress(spec, it, kind, ep):
    print(it, kind, ep.success, ep.reason, round(ep.sim_time_s, 1), flush=True)
recs = run_learning(RunSpec("door", True, seed), cfg, [traj], make_world, Path(f"/work/runs/door/{name}"), progress)
for r in recs:
    print({k: r.get(k) for k in ("iteration", "interaction_s", "wall_s", "collect_success", "eval_success", "eval_reasons")}, flush=True)
