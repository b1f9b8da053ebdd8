#!/bin/bash
# Dev check of the shortening that comes no nearer what is avoided (HEAD at /work/dev07d) against
# d035e82's shortening (ref-after/, san-after/): reference programs, staying on, at least a
# distance and staying away (ground truth), and staying away with noisy pixels, dev seeds 0-19,
# both splits, 1 worker beside v4.2.
cd /work/main
export MUJOCO_GL=egl PYTHONPATH=/work/dev07d/src
R=/work/runs/dev07
echo "$(date) start near-gt" >> $R/progress.log
.venv/bin/voxposer bench --llm reference --tasks move_to_pos_staying_on_preposition,move_to_pos_min_distance,push_to_pos_avoid_obstacle \
  --seeds dev --episodes 20 --workers 1 --out $R/near-gt > $R/near-gt.log 2>&1
echo "$(date) start near-noisy" >> $R/progress.log
.venv/bin/voxposer bench --llm reference --perception colour-depth-noisy --tasks push_to_pos_avoid_obstacle \
  --seeds dev --episodes 20 --workers 1 --out $R/near-noisy > $R/near-noisy.log 2>&1
echo "$(date) near done" >> $R/progress.log
