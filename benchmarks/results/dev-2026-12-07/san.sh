#!/bin/bash
# Dev check for issue "perception": staying away with noisy pixels (reference programs,
# colour-depth-noisy), dev seeds 0-19 (0-9 first, then --resume), both splits, before (5528781 at /work/dev07) and after
# (d035e82 at /work/dev07c) the planner's shortening; 1 worker each, beside v4.2.
cd /work/main
export MUJOCO_GL=egl
R=/work/runs/dev07
for side in after before; do
  wt=/work/dev07c; [ $side = before ] && wt=/work/dev07
  res=""; [ -f $R/san-$side/episodes.jsonl ] && res="--resume"
  echo "$(date) start san-$side $res" >> $R/progress.log
  PYTHONPATH=$wt/src .venv/bin/voxposer bench --llm reference --perception colour-depth-noisy \
    --tasks push_to_pos_avoid_obstacle --seeds dev --episodes 20 --workers 1 $res \
    --out $R/san-$side > $R/san-$side.log 2>&1
  echo "$(date) end san-$side rc=$?" >> $R/progress.log
done
