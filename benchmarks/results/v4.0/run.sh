#!/bin/bash
# Benchmark v4.0 (issues "open-set instructions" and "perception": a push's stroke keeps to its
# line): the frozen commit checked out at /work/frozen40 (git worktree add --detach
# /work/frozen40 bd3fcf5), test seeds, each step resumable (--resume, same commit).
#   ref-staying-away-noisy/  reference programs, colour-depth-noisy, staying away, both
#                            attribute splits, test seeds 100000-100019 (as v3.8's cell)
#   ref-staying-away-gt/     the same with ground truth
#   paraphrased/             the default model, test phrasings, seen attributes, test seeds
#                            100000-100009, an empty response cache (as v3.6)
#   default/                 the default model, the seen templates, the same seeds and cache use
cd /work/main
export PYTHONPATH=/work/frozen40/src MUJOCO_GL=egl
R=/work/runs/v40
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
SA="--llm reference --tasks push_to_pos_avoid_obstacle --splits seen,unseen --episodes 20"
step ref-staying-away-noisy $SA --perception colour-depth-noisy
step ref-staying-away-gt $SA --perception ground-truth
step paraphrased --llm default --splits seen --episodes 10 --fresh-cache --instructions paraphrased
step default --llm default --splits seen --episodes 10 --fresh-cache
echo "$(date) all done" >> $R/progress.log
