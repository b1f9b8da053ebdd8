#!/bin/bash
# Final test-seed runs on the frozen commit in /work/final; resumable.
cd /work/main
export PYTHONPATH=/work/final/src MUJOCO_GL=egl
R=/work/runs/final
step() {  # name, args...
  name=$1; shift
  [ -f $R/$name.done ] && return
  res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench "$@" --seeds test --out $R/$name $res --no-plot >> $R/$name.log 2>&1 && touch $R/$name.done
  echo "$(date) end $name rc=$?" >> $R/progress.log
}
step reference --llm reference --episodes 20
step reference-blind --llm reference-blind --episodes 20
step default --llm default --episodes 20 --fresh-cache
step default-paraphrased --llm default --instructions paraphrased --splits seen --episodes 10 --fresh-cache
step default-multistep --llm default --suite multistep --splits seen --episodes 10 --fresh-cache
step default-ui --llm default --instructions unseen --splits unseen --episodes 10 --fresh-cache
step llm-primitives --method llm_primitives --llm default --episodes 20 --fresh-cache
echo "$(date) all done" >> $R/progress.log
