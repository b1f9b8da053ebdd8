#!/bin/bash
# Benchmark v4.6: the pushing hand's sweep band and descent limit (9accec1) on the test seeds,
# the cells they touch (every pushing task, three perceptions), then issue "open-set
# instructions"' default-model run on the same commit. The frozen commit checked out at /work/frozen46 (git worktree add --detach
# /work/frozen46 <commit>, named in README.md); each step resumable (--resume, same commit).
#   sa-noisy/, sa-tracked-noisy/, sa-gt/   staying away, reference programs, test seeds
#       100000-100019, both attribute splits, 20 per cell, three perceptions (as v4.5)
#   push-noisy/, push-gt/, push-tracked-noisy/   the other pushing tasks (to a position,
#       along the line, keeping on a region, closing the drawer), reference programs (as v4.5)
#   default/, paraphrased/   the default model, test seeds 100000-100009, seen attributes, the
#       seen templates and the test phrasings, an empty response cache per step (as v4.3)
cd /work/main
export PYTHONPATH=/work/frozen46/src MUJOCO_GL=egl
R=/work/runs/v46
mkdir -p $R
step() {  # name, workers, then the bench arguments
  local name=$1 workers=$2; shift 2
  [ -f $R/$name.done ] && return
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench --seeds test --workers $workers --out $R/$name $res "$@" >> $R/$name.log 2>&1
  local rc=$?
  [ $rc -eq 0 ] && touch $R/$name.done
  echo "$(date) end $name rc=$rc" >> $R/progress.log
}
SA="--llm reference --episodes 20 --tasks push_to_pos_avoid_obstacle"
step sa-noisy 1 $SA --perception colour-depth-noisy
step sa-tracked-noisy 1 $SA --perception colour-depth-tracked-noisy
step sa-gt 1 $SA --perception ground-truth
P="--llm reference --episodes 20 --tasks push_to_pos,push_along_line,push_stay_on_region,close_drawer"
step push-noisy 2 $P --perception colour-depth-noisy
step push-gt 2 $P --perception ground-truth
step push-tracked-noisy 2 $P --perception colour-depth-tracked-noisy
M="--llm default --splits seen --episodes 10 --fresh-cache"
step default 2 $M
step paraphrased 2 $M --instructions paraphrased
echo "$(date) all done" >> $R/progress.log
