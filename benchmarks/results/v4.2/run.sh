#!/bin/bash
# Benchmark v4.2 (issue "open-set instructions": a speed zone planned as a destination folded
# into the motion, staying-on clauses read in more wordings, one pattern for the hand's motions;
# the planner's path straightened where a straight segment costs no more): the frozen commit
# checked out at /work/frozen42 (git worktree add --detach /work/frozen42 <commit>, named in
# README.md), the default model, test seeds 100000-100009, seen attributes, an empty response
# cache per step (as v4.1); each step resumable (--resume, same commit).
#   paraphrased/  the test phrasings
#   default/      the seen templates
#   vague-relational/  the vague-relational test words
#   multistep/    the multi-step suite
#   llm_latency.txt    benchmarks/llm_latency.py --mode suite (warm LLM time per instruction)
cd /work/main
export PYTHONPATH=/work/frozen42/src MUJOCO_GL=egl
R=/work/runs/v42
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
step vague-relational $M --instructions vague-relational
step multistep $M --suite multistep
if [ ! -s $R/llm_latency.txt ]; then
  .venv/bin/python /work/frozen42/benchmarks/llm_latency.py --mode suite > $R/llm_latency.txt 2>&1
  echo "$(date) end llm_latency rc=$?" >> $R/progress.log
fi
echo "$(date) all done" >> $R/progress.log
