#!/bin/bash
# Dev check of the planner change (any-angle shortening, tighter A* bound, Gaussian by matrix
# products): reference programs on every task, both attribute splits, dev seeds 0-19 (0-5 first, then --resume), before
# (5528781 at /work/dev07) and after (f4d4938 at /work/dev07b). Records in /work/runs/dev07.
cd /work/main
export MUJOCO_GL=egl
R=/work/runs/dev07
for side in after before; do
  wt=/work/dev07b; [ $side = before ] && wt=/work/dev07
  res=""; [ -f $R/ref-$side/episodes.jsonl ] && res="--resume"
  echo "$(date) start ref-$side" >> $R/progress.log
  PYTHONPATH=$wt/src .venv/bin/voxposer bench --llm reference --splits seen,unseen --seeds dev \
    --episodes 20 --workers 2 --out $R/ref-$side $res > $R/ref-$side.log 2>&1
  echo "$(date) end ref-$side rc=$?" >> $R/progress.log
done
