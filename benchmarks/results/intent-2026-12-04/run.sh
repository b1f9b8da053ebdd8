#!/bin/bash
# intent checks on the test seeds: the default model, seen instructions, test seeds 100000-100001,
# on the frozen commit in /work/frozen2 (git worktree add /work/frozen2 9017577); resumable.
cd /work/main
export PYTHONPATH=/work/frozen2/src MUJOCO_GL=egl OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
R=/work/runs/i12
res=""; [ -f $R/test/episodes.jsonl ] && res="--resume"
echo "$(date) start test $res" >> $R/progress.log
.venv/bin/voxposer bench --llm default --seeds test --episodes 2 --fresh-cache --workers 1 --out $R/test $res --no-plot >> $R/test.log 2>&1
echo "$(date) end test rc=$?" >> $R/progress.log
