#!/bin/bash
# Dev check (issue "open-set instructions"): staying on and velocity in a region on dev seeds
# and dev phrasings only, the default model, seen attributes, --fresh-cache, HEAD 5528781
# checked out at /work/dev07. Records in /work/runs/dev07, copied here when complete.
cd /work/main
export PYTHONPATH=/work/dev07/src MUJOCO_GL=egl
R=/work/runs/dev07; mkdir -p $R
T=move_to_pos_staying_on_preposition,move_to_pos_velocity_in_region
M="--llm default --splits seen --fresh-cache --workers 2 --instructions paraphrased --tasks $T"
D=benchmarks/results/dev-2026-12-07
echo "$(date) start x8" >> $R/progress.log
.venv/bin/python $D/extra_dev8.py bench $M --seed 25 --episodes 12 --out $R/x8 > $R/x8.log 2>&1
echo "$(date) start x7" >> $R/progress.log
.venv/bin/python benchmarks/results/dev-2026-12-06h/extra_dev7.py bench $M --seed 10 --episodes 6 --out $R/x7 > $R/x7.log 2>&1
echo "$(date) start dev25" >> $R/progress.log
.venv/bin/voxposer bench $M --seed 25 --episodes 25 --out $R/dev25 > $R/dev25.log 2>&1
echo "$(date) all done" >> $R/progress.log
