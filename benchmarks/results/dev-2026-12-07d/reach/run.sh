#!/bin/bash
# Dev check of the pushing-reach limit (push_reach_m 0.72): reference programs, dev seeds,
# both attribute splits; "after" = /work/dev-reach (HEAD 9570652 + the change); "before" =
# /work/runs/dev-refuse (9d299f2, behaviour as 9570652).
#   sa-noisy: staying away, colour-depth-noisy, dev seeds 0-19
#   gt-push:  push tasks (free objects), ground truth, dev seeds 0-9
cd /work/main
export MUJOCO_GL=egl PYTHONPATH=/work/dev-reach/src
R=/work/runs/dev-reach
arm() {
  local name=$1; shift
  [ -f $R/$name.done ] && return
  local res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
  echo "$(date) start $name" >> $R/progress.log
  .venv/bin/voxposer bench --llm reference --seeds dev --workers 1 --out $R/$name $res --no-plot "$@" >> $R/$name.log 2>&1 && touch $R/$name.done
  echo "$(date) end $name rc=$?" >> $R/progress.log
}
case $1 in
  sa) arm $2 --tasks push_to_pos_avoid_obstacle --perception colour-depth-noisy --episodes 20 ;;
  gt) arm $2 --tasks push_to_pos,push_to_pos_avoid_obstacle,push_along_line,push_stay_on_region --episodes 10 ;;
esac
