#!/bin/bash
# Benchmark v3.8 (issue "perception"): reference programs with the pixel perception and the
# sensor model (--perception colour-depth-noisy), the cameras now registered against each other,
# on the frozen commit checked out at /work/frozen38 (git worktree add --detach /work/frozen38
# 1d5945b), test seeds 100000-100019, both attribute splits, as v3.1 and v3.7; resumes
# (--resume) after an interruption.
cd /work/main
export PYTHONPATH=/work/frozen38/src MUJOCO_GL=egl
R=/work/runs/v38
mkdir -p $R
res=""; [ -f $R/reference-noisy/episodes.jsonl ] && res="--resume"
echo "$(date) start reference-noisy $res" >> $R/progress.log
.venv/bin/voxposer bench --llm reference --perception colour-depth-noisy --seeds test \
  --episodes 20 --workers 2 --out $R/reference-noisy $res >> $R/reference-noisy.log 2>&1
echo "$(date) end reference-noisy rc=$?" >> $R/progress.log
