#!/bin/bash
# pose.sh CODE DATA OUT.json [ROWS...]: benchmarks/pose_table.py of CODE's tree (its library) on DATA, every part,
# 40 frames, 312x96, photo crops, one thread; rows default gt_fit pred_fit. env RUNS: the demo's runs (default w0);
# env FIT: FitSettings fields to change (KEY=VALUE ...).
RUNS=${RUNS:-/tmp/s21data/demo/out/runs}; PY=/work/main/.venv/bin/python
T=$1; DATA=$2; OUT=$3; shift 3
ROWS=("$@"); [ ${#ROWS[@]} -eq 0 ] && ROWS=(gt_fit pred_fit)
CK=$(ls $RUNS/geometric/checkpoints/best-*.ckpt | head -1)
SEM=$(ls $RUNS/semantic/checkpoints/best-*.ckpt | head -1)
cd "$T" && PYTHONPATH=$T/src:$T OMP_NUM_THREADS=1 nice -n 5 $PY benchmarks/pose_table.py \
  --geometric "$CK" --semantic "$SEM" --data-root "$DATA" --part all --max-frames 40 --threads 1 \
  --image-size 312 96 --min-pixels 64 --rows "${ROWS[@]}" --crops photo --out "$OUT" ${FIT:+--fit $FIT} > /dev/null
