#!/bin/bash
# U-Net + MP on unseen instructions (paper Table 2's UI column): v3.2's checkpoint (trained on
# the seen templates of dev seeds), the frozen commit checked out at /work/frozen-unet (git
# worktree add --detach /work/frozen-unet <commit>, named in README.md), test seeds
# 100000-100019, both attribute splits; resumable (--resume, same commit).
#   paraphrased/  the paraphrase split's test phrasings (instructions it never saw)
#   seen/         the templates again, on the same commit (v3.2 ran them on a4f1dd0)
cd /work/main
export PYTHONPATH=/work/frozen-unet/src MUJOCO_GL=egl
R=/work/runs/unet-ui
mkdir -p $R
step() {  # name, then the bench arguments
  local name=$1; shift
  [ -f $R/$name.done ] && return
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench --seeds test --workers 1 --out $R/$name $res "$@" >> $R/$name.log 2>&1
  local rc=$?
  [ $rc -eq 0 ] && touch $R/$name.done
  echo "$(date) end $name rc=$rc" >> $R/progress.log
}
M="--method unet_mp --unet-checkpoint benchmarks/results/v3.2/unet-checkpoint/model.pt --episodes 20"
step paraphrased $M --instructions paraphrased
step seen $M
echo "$(date) all done" >> $R/progress.log
