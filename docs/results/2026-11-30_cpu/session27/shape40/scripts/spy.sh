#!/bin/bash
# spy.sh CODE DATA OUT_PREFIX: pose.sh's pose table, row gt_fit only, through spy_pose.py: OUT_PREFIX.json (the pose
# table) and OUT_PREFIX.spy.json (every fine hypothesis per object). env RUNS: the demo's runs (default w0).
HERE=$(cd $(dirname $0) && pwd); RUNS=${RUNS:-/tmp/s21data/demo/out/runs}; PY=/work/main/.venv/bin/python
T=$1; DATA=$2; OUT=$3
CK=$(ls $RUNS/geometric/checkpoints/best-*.ckpt | head -1)
SEM=$(ls $RUNS/semantic/checkpoints/best-*.ckpt | head -1)
cd "$T" && PYTHONPATH=$T/src:$T OMP_NUM_THREADS=1 nice -n 5 $PY $HERE/spy_pose.py "$OUT.spy.json" \
  --geometric "$CK" --semantic "$SEM" --data-root "$DATA" --part all --max-frames 40 --threads 1 \
  --image-size 312 96 --min-pixels 64 --rows gt_fit --crops photo --out "$OUT.json" > /dev/null
