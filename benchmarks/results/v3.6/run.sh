#!/bin/bash
# Benchmark v3.6 (issue "open-set instructions"): the default model on the frozen commit checked
# out at /work/frozen36 (git worktree add --detach /work/frozen36 9c04c02), test seeds, an empty
# response cache at the start of each run; each step resumes (--resume) after an interruption.
#   paraphrased/       test phrasings, seen attributes, test seeds 100000-100009 (as v3.3-v3.5)
#   default/           the seen templates on the same seeds and split (no loss on the templates)
#   vague-relational/  the test phrasings with blocks named by relation and quantities said
#                      vaguely, the same seeds
#   multistep/         the multi-step suite, test seeds 100000-100009 per entry
#   llm_latency.txt    benchmarks/llm_latency.py --mode suite (warm LLM time per instruction)
cd /work/main
export PYTHONPATH=/work/frozen36/src MUJOCO_GL=egl
R=/work/runs/v36
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
step vague-relational --instructions vague-relational
step multistep --suite multistep
if [ ! -s $R/llm_latency.txt ]; then
  .venv/bin/python /work/frozen36/benchmarks/llm_latency.py --mode suite > $R/llm_latency.txt 2>&1
  echo "$(date) end llm_latency rc=$?" >> $R/progress.log
fi
