#!/bin/bash
# Benchmark v4.7 (issue "open-set instructions" on the final code of the fifteenth session: the
# pushing as v4.5, staying away's layouts of 0fa3f3c): the frozen commit checked out at
# /work/frozen47 (git worktree add --detach /work/frozen47 <commit>, named in README.md), the
# default model, test seeds 100000-100009, seen attributes, an empty response cache per step (as
# v4.3); each step resumable (--resume, same commit).
#   default/      the seen templates
#   paraphrased/  the test phrasings
cd /work/main
export PYTHONPATH=/work/frozen47/src MUJOCO_GL=egl
R=/work/runs/v47
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
M="--llm default --splits seen --episodes 10 --fresh-cache"
step default $M
step paraphrased $M --instructions paraphrased
echo "$(date) all done" >> $R/progress.log
