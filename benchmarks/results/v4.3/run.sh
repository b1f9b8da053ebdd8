#!/bin/bash
# Benchmark v4.3 (issue "open-set instructions": v4.2's code and the hand's planner keeping its
# distance when it straightens a path, pushes unchanged; the sandbox's memory watch counting
# from its lowest reading): the frozen commit checked out at /work/frozen43 (git worktree add
# --detach /work/frozen43 <commit>, named in README.md), the default model, test seeds
# 100000-100009, seen attributes, an empty response cache per step (as v4.2); each step
# resumable (--resume, same commit).
#   default/      the seen templates
#   paraphrased/  the test phrasings
cd /work/main
export PYTHONPATH=/work/frozen43/src MUJOCO_GL=egl
R=/work/runs/v43
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
