#!/bin/bash
# Dev check of the plan mends with the default model (d035e82 at /work/dev07c): the extra dev
# phrasings of extra_dev8.py on the ad-hoc seeds where they failed (26-34) and extra_dev7.py's
# seed 14, both tasks, seen attributes, --fresh-cache. Records in /work/runs/dev07.
cd /work/main
export PYTHONPATH=/work/dev07c/src MUJOCO_GL=egl
R=/work/runs/dev07
T=move_to_pos_staying_on_preposition,move_to_pos_velocity_in_region
M="--llm default --splits seen --fresh-cache --workers 2 --instructions paraphrased --tasks $T"
D=benchmarks/results/dev-2026-12-07
echo "$(date) start x8-after" >> $R/progress.log
.venv/bin/python $D/extra_dev8.py bench $M --seed 26 --episodes 9 --out $R/x8-after > $R/x8-after.log 2>&1
echo "$(date) start x7-after" >> $R/progress.log
.venv/bin/python benchmarks/results/dev-2026-12-06h/extra_dev7.py bench $M --seed 14 --episodes 1 --out $R/x7-after > $R/x7-after.log 2>&1
echo "$(date) confirm done" >> $R/progress.log
