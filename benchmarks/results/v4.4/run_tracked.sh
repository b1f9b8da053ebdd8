#!/bin/bash
# Benchmark v4.4, second part: the same cells with the pixel perception carrying its labels
# between detections (colour-depth-tracked-noisy), on the same frozen commit (/work/frozen44),
# after run.sh's steps (it waits for them); resumable (--resume, same commit).
#   reference-tracked-noisy/
cd /work/main
export PYTHONPATH=/work/frozen44/src MUJOCO_GL=egl
R=/work/runs/v44
until grep -q "all done" $R/progress.log 2>/dev/null; do sleep 30; done
name=reference-tracked-noisy
[ -f $R/$name.done ] && exit 0
res=""; [ -f $R/$name/episodes.jsonl ] && res="--resume"
echo "$(date) start $name $res" >> $R/progress.log
.venv/bin/voxposer bench --seeds test --workers 2 --out $R/$name $res --llm reference \
  --episodes 20 --perception colour-depth-tracked-noisy >> $R/$name.log 2>&1
rc=$?
[ $rc -eq 0 ] && touch $R/$name.done
echo "$(date) end $name rc=$rc" >> $R/progress.log
