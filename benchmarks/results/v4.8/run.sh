#!/bin/bash
# Benchmark v4.8 (issue "open-set instructions" on the code of the sixteenth session: v4.7's
# code with the two plan mends of dev-2026-12-08): the frozen commit checked out at
# /work/frozen48 (git worktree add --detach /work/frozen48 657bec3), the default model, test
# seeds 100000-100009, seen attributes, an empty response cache per step (as v4.7); each step
# resumable (--resume, same commit). The paraphrased step first (the open target), then the
# templates.
#   paraphrased/  the test phrasings
#   default/      the seen templates
cd /work/main
export PYTHONPATH=/work/frozen48/src MUJOCO_GL=egl
R=/work/runs/v48
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
step paraphrased $M --instructions paraphrased
step default $M
echo "$(date) all done" >> $R/progress.log
