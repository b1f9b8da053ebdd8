#!/bin/bash
# Dev check: the default model on "at least a distance" (templates, dev seeds 0-19, seen), the
# planner's shortening on (HEAD), off, and with the distance rule; one worker each, in turn.
cd /work/main
export MUJOCO_GL=egl
R=/work/runs/mindist
mkdir -p $R
while pgrep -f "runs/dropnoisy" > /dev/null; do sleep 20; done
for arm in on:/work/dev_on nosc:/work/dev_nosc keep:/work/dev_keep; do
  name=${arm%%:*}; src=${arm#*:}/src
  echo "$(date) start $name" >> $R/progress.log
  PYTHONPATH=$src .venv/bin/voxposer bench --llm default --tasks move_to_pos_min_distance \
    --seeds dev --episodes 20 --splits seen --workers 1 --out $R/$name > $R/$name.log 2>&1
  echo "$(date) end $name rc=$?" >> $R/progress.log
done
