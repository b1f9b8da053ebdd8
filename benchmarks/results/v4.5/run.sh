#!/bin/bash
# Benchmark v4.5 (issue "perception"): reference programs on every cell, test seeds
# 100000-100019, both attribute splits, 20 episodes per cell; the frozen commit checked out at
# /work/frozen45 (git worktree add --detach /work/frozen45 <commit>, named in README.md); each
# step resumable (--resume, same commit).
#   reference-noisy/          the weight-free pixel perception with the sensor model
#   reference-tracked-noisy/  the same with labels carried between detections
#   reference-gt/             the simulator's segmentation (ground-truth), the same episodes
cd /work/main
export PYTHONPATH=/work/frozen45/src MUJOCO_GL=egl
R=/work/runs/v45
mkdir -p $R
step() {  # name, then the bench arguments
  local name=$1; shift
  [ -f $R/$name.done ] && return
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench --seeds test --workers 2 --out $R/$name $res "$@" >> $R/$name.log 2>&1
  local rc=$?
  [ $rc -eq 0 ] && touch $R/$name.done
  echo "$(date) end $name rc=$rc" >> $R/progress.log
}
M="--llm reference --episodes 20"
step reference-noisy $M --perception colour-depth-noisy
step reference-tracked-noisy $M --perception colour-depth-tracked-noisy
step reference-gt $M --perception ground-truth
echo "$(date) all done" >> $R/progress.log
