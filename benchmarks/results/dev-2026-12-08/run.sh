#!/bin/bash
# Dev check (issue "open-set instructions"): staying on and velocity within a distance, the two
# tasks short of the paraphrase target on the test seeds in v4.2, v4.3 and v4.7, on new ad-hoc
# dev seeds with a third set of extra dev phrasings (extra_dev9.py) and with the dev phrasings;
# the default model, seen attributes, --fresh-cache, HEAD 89be64d checked out at /work/dev08.
# Records in /work/runs/dev08, copied here when complete.
cd /work/main
export PYTHONPATH=/work/dev08/src MUJOCO_GL=egl
R=/work/runs/dev08; mkdir -p $R
T=move_to_pos_staying_on_preposition,move_to_pos_velocity_near_obj
M="--llm default --splits seen --fresh-cache --workers 2 --instructions paraphrased --tasks $T"
D=benchmarks/results/dev-2026-12-08
step() {  # name, then the bench arguments
  local name=$1; shift
  [ -f $R/$name.done ] && return
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  "$@" $res --out $R/$name >> $R/$name.log 2>&1 && touch $R/$name.done
  echo "$(date) end $name" >> $R/progress.log
}
step x9 .venv/bin/python $D/extra_dev9.py bench $M --seed 300 --episodes 12
step dev300 .venv/bin/voxposer bench $M --seed 312 --episodes 12
echo "$(date) all done" >> $R/progress.log
