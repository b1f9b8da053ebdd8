#!/bin/bash
# Benchmark v3.4 (issue "open-set instructions"): the default model on the frozen commit checked
# out at /work/frozen34 (git worktree add --detach /work/frozen34 <commit>), test seeds, an empty
# response cache at the start of each run; each step resumes (--resume) after an interruption.
#   paraphrased/  test phrasings, seen attributes, test seeds 100000-100009 (as v3.3's)
#   default/      the seen templates on the same seeds and split (no loss on the templates)
cd /work/main
export PYTHONPATH=/work/frozen34/src MUJOCO_GL=egl
R=/work/runs/v34
mkdir -p $R
step() {  # name, then the bench arguments
  local name=$1; shift
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench --llm default --seeds test --episodes 10 --splits seen --fresh-cache \
    --workers 2 --out $R/$name $res "$@" >> $R/$name.log 2>&1
  echo "$(date) end $name rc=$?" >> $R/progress.log
}
step paraphrased --instructions paraphrased
step default
# added after the two steps above finished (same frozen commit): the multi-step suite, its
# first 5 test seeds per entry (v3's default-multistep/ ran 10)
step multistep --suite multistep --episodes 5
