#!/bin/bash
# Benchmark v4.2, reference-program cells of issue "perception" (as v4.0's): the frozen commit
# d035e82 at /work/frozen42, staying away, both attribute splits, test seeds 100000-100019,
# 1 worker (beside run.sh's model steps); each step resumable on the same commit.
#   ref-staying-away-noisy/  reference programs, colour-depth-noisy
#   ref-staying-away-gt/     the same with ground truth
cd /work/main
export PYTHONPATH=/work/frozen42/src MUJOCO_GL=egl
R=/work/runs/v42
mkdir -p $R
step() {  # name, then the bench arguments
  local name=$1; shift
  [ -f $R/$name.done ] && return
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench --seeds test --workers 1 --out $R/$name $res "$@" >> $R/$name.log 2>&1
  local rc=$?
  [ $rc -eq 0 ] && touch $R/$name.done
  echo "$(date) end $name rc=$rc" >> $R/progress.log
}
SA="--llm reference --tasks push_to_pos_avoid_obstacle --splits seen,unseen --episodes 20"
step ref-staying-away-noisy $SA --perception colour-depth-noisy
step ref-staying-away-gt $SA --perception ground-truth
