#!/bin/bash
# Dev check of label tracking: reference programs, noisy pixels, dev seeds, tracked then not.
cd /work/main
export PYTHONPATH=/work/dev-track/src MUJOCO_GL=egl
R=/work/runs/dev-track
for arm in colour-depth-tracked-noisy colour-depth-noisy; do
  [ -f $R/$arm.done ] && continue
  res=""; [ -f $R/$arm/episodes.jsonl ] && res="--resume"
  echo "$(date) start $arm" >> $R/progress.log
  .venv/bin/voxposer bench --llm reference --perception $arm --seeds dev --episodes 3 --splits seen --workers 1 --out $R/$arm $res --no-plot >> $R/$arm.log 2>&1 && touch $R/$arm.done
  echo "$(date) end $arm rc=$?" >> $R/progress.log
done
