#!/bin/bash
# land.sh CODE DATA OUT [ROWS...]: landscape.py (the fit's loss landscape around each winner) run as diag.sh runs
# diag_pose.py: pose table OUT.json, landscape OUT.land.json. env RUNS: the demo's runs folder (default w0).
HERE=$(cd $(dirname $0) && pwd); RUNS=${RUNS:-/tmp/s21data/demo/out/runs}; PY=/work/main/.venv/bin/python
T=$1; DATA=$2; OUT=$3; shift 3
ROWS=("$@"); [ ${#ROWS[@]} -eq 0 ] && ROWS=(gt_fit)
CK=$(ls $RUNS/geometric/checkpoints/best-*.ckpt | head -1)
SEM=$(ls $RUNS/semantic/checkpoints/best-*.ckpt | head -1)
cd "$T" && PYTHONPATH=$T/src:$T OMP_NUM_THREADS=1 nice -n 5 $PY $HERE/landscape.py "$OUT.land.json" \
  --geometric "$CK" --semantic "$SEM" --data-root "$DATA" --part all --max-frames 40 --threads 1 \
  --image-size 312 96 --min-pixels 64 --rows "${ROWS[@]}" --crops photo --out "$OUT.json"
