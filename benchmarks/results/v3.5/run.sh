#!/bin/bash
# Benchmark v3.5 (issue "open-set instructions"): the default model on the frozen commit checked
# out at /work/frozen35 (git worktree add --detach /work/frozen35 7af255d), test seeds, an empty
# response cache at the start of each run; each step resumes (--resume) after an interruption.
#   multistep/         the multi-step suite, test seeds 100000-100009 per entry (v3 ran these ten,
#                      v3.4 the first five)
#   paraphrased/       test phrasings, seen attributes, test seeds 100000-100009 (as v3.3/v3.4)
#   default/           the seen templates on the same seeds and split (no loss on the templates)
#   vague-relational/  the test phrasings with blocks named by relation and quantities said
#                      vaguely, the same seeds
cd /work/main
export PYTHONPATH=/work/frozen35/src MUJOCO_GL=egl
R=/work/runs/v35
mkdir -p $R
step() {  # name, then the bench arguments
  local name=$1; shift
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench --llm default --seeds test --episodes 10 --splits seen --fresh-cache \
    --workers 2 --out $R/$name $res "$@" >> $R/$name.log 2>&1
  echo "$(date) end $name rc=$?" >> $R/progress.log
}
step multistep --suite multistep
step paraphrased --instructions paraphrased
step default
step vague-relational --instructions vague-relational
