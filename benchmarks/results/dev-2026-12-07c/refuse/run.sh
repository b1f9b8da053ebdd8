#!/bin/bash
# Dev check of the refused-push rule: reference programs, ground truth, dev seeds 0-9, both
# attribute splits, the push tasks; before = 9367700 (/work/dev-track), after = the rule's commit
# (/work/dev-refuse).
cd /work/main
export MUJOCO_GL=egl
R=/work/runs/dev-refuse
T="push_to_pos,push_to_pos_avoid_obstacle,push_along_line,push_stay_on_region,close_drawer"
for arm in after before; do
  [ -f $R/$arm.done ] && continue
  src=/work/dev-refuse/src; [ $arm = before ] && src=/work/dev-track/src
  res=""; [ -f $R/$arm/episodes.jsonl ] && res="--resume"
  echo "$(date) start $arm" >> $R/progress.log
  PYTHONPATH=$src .venv/bin/voxposer bench --llm reference --tasks $T --seeds dev --episodes 10 --workers 1 --out $R/$arm $res --no-plot >> $R/$arm.log 2>&1 && touch $R/$arm.done
  echo "$(date) end $arm rc=$?" >> $R/progress.log
done
# staying away with noisy pixels, dev seeds 0-19 (as dev-2026-12-07b/ee-keep-noisy, 35/40)
for arm in sa-noisy-after sa-noisy-before; do
  [ -f $R/$arm.done ] && continue
  src=/work/dev-refuse/src; [ $arm = sa-noisy-before ] && src=/work/dev-track/src
  res=""; [ -f $R/$arm/episodes.jsonl ] && res="--resume"
  echo "$(date) start $arm" >> $R/progress.log
  PYTHONPATH=$src .venv/bin/voxposer bench --llm reference --tasks push_to_pos_avoid_obstacle --perception colour-depth-noisy --seeds dev --episodes 20 --workers 1 --out $R/$arm $res --no-plot >> $R/$arm.log 2>&1 && touch $R/$arm.done
  echo "$(date) end $arm rc=$?" >> $R/progress.log
done
