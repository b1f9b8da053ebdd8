#!/bin/bash
# Dev check: push along the line with noisy pixels, with and without the pushing reach
# (8963b21 as frozen for v4.4 = "band"; the same with push_reach_m (0, 0) = "noband"),
# reference programs, dev seeds 0-19, both splits, 1 worker per arm.
cd /work/main
export MUJOCO_GL=egl
R=/work/runs/dev-line
arm=$1; src=/work/frozen44/src; [ $arm = noband ] && src=/work/dev-noband/src
res=""; [ -f $R/$arm/episodes.jsonl ] && res="--resume"
echo "$(date) start $arm" >> $R/progress.log
PYTHONPATH=$src .venv/bin/voxposer bench --llm reference --tasks push_along_line --perception colour-depth-noisy --seeds dev --episodes 20 --workers 1 --out $R/$arm $res --no-plot >> $R/$arm.log 2>&1 && touch $R/$arm.done
echo "$(date) end $arm rc=$?" >> $R/progress.log
