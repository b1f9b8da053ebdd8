#!/bin/bash
# Benchmark v3.9 (issue "perception": the default model's drop from ground truth to noisy
# pixels, per cell): the bundled default model on the frozen commit checked out at /work/frozen39
# (git worktree add --detach /work/frozen39 9894ebd), seen instructions, seen attributes, test
# seeds 100000-100009, --fresh-cache, once with --perception colour-depth-noisy and once with
# ground-truth (same commit, so the difference is the perception's); resumable (--resume, same
# commit) across sessions.
cd /work/main
export PYTHONPATH=/work/frozen39/src MUJOCO_GL=egl
R=/work/runs/v39
mkdir -p $R
step() {  # name, args...
  name=$1; shift
  [ -f $R/$name.done ] && return
  res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench "$@" --seeds test --out $R/$name $res >> $R/$name.log 2>&1
  rc=$?
  [ $rc -eq 0 ] && touch $R/$name.done
  echo "$(date) end $name rc=$rc" >> $R/progress.log
}
step default-noisy --llm default --perception colour-depth-noisy --splits seen --episodes 10 --fresh-cache
step default-gt --llm default --perception ground-truth --splits seen --episodes 10 --fresh-cache
echo "$(date) all done" >> $R/progress.log
