#!/bin/bash
# diag.sh CODE DATA OUT_PREFIX [ROWS...]: pose.sh's pose table (CODE's library and pose_table.py) run through
# diag_pose.py: OUT_PREFIX.json (the pose table) and OUT_PREFIX.diag.json (the fit's decisions per object).
# env RUNS: the demo's runs folder (default w0, /tmp/s21data/demo/out/runs); FIT: FitSettings overrides for
# pose_table.py's --fit (e.g. FIT="camera_height=1.536"; session 26 axis40).
HERE=$(cd $(dirname $0) && pwd); RUNS=${RUNS:-/tmp/s21data/demo/out/runs}; PY=/work/main/.venv/bin/python
T=$1; DATA=$2; OUT=$3; shift 3
ROWS=("$@"); [ ${#ROWS[@]} -eq 0 ] && ROWS=(gt_branch gt_fit pred_fit)
CK=$(ls $RUNS/geometric/checkpoints/best-*.ckpt | head -1)
SEM=$(ls $RUNS/semantic/checkpoints/best-*.ckpt | head -1)
cd "$T" && PYTHONPATH=$T/src:$T OMP_NUM_THREADS=1 nice -n 5 $PY $HERE/diag_pose.py "$OUT.diag.json" \
  --geometric "$CK" --semantic "$SEM" --data-root "$DATA" --part all --max-frames 40 --threads 1 \
  --image-size 312 96 --min-pixels 64 --rows "${ROWS[@]}" --crops photo --out "$OUT.json" ${FIT:+--fit $FIT}
