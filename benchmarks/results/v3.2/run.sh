#!/bin/bash
# U-Net + MP on the test seeds, on the frozen commit checked out in /work/frozen
# (git worktree add /work/frozen a4f1dd0), with the checkpoint of unet-checkpoint/; resumable.
cd /work/main
export PYTHONPATH=/work/frozen/src MUJOCO_GL=egl
R=/work/runs/v3.2
mkdir -p $R
step() {  # name, args...
  name=$1; shift
  [ -f $R/$name.done ] && return
  res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name $res" >> $R/progress.log
  .venv/bin/voxposer bench "$@" --seeds test --out $R/$name $res --no-plot >> $R/$name.log 2>&1 && touch $R/$name.done
  echo "$(date) end $name rc=$?" >> $R/progress.log
}
step unet-mp --method unet_mp --unet-checkpoint benchmarks/results/v3.2/unet-checkpoint/model.pt --episodes 20
echo "$(date) all done" >> $R/progress.log
