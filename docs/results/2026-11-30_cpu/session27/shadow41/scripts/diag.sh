#!/bin/bash
# diag.sh SRC TAG SOURCE [OVERRIDE ...]: diag.py (per-pair dumps of the photo removal) on the tuning cf trees
# cf31/cf33/cf39 with code tree SRC, source scene SOURCE (semantic: predicted; oracle: ground-truth geometry), fill
# rays, deletes, w0 weights, further sdn3d-bench overrides (e.g. +photo.faint_light=0.95); dumps to
# /tmp/s27data/shadow41/diag/TAG<seed>_<source>/, one tree after another, threads 1, nice 5.
SRC=$1; TAG=$2; SOURCE=${3:-semantic}; shift 3
D=$(cd "$(dirname "$0")" && pwd); O=/tmp/s27data/shadow41/diag
CK="checkpoints.semantic=/tmp/s21data/demo/out/runs/semantic/checkpoints/inference.pt"
CK="$CK checkpoints.geometric=/tmp/s21data/demo/out/runs/geometric/checkpoints/inference.pt"
[ "$SOURCE" = semantic ] || CK=""
for S in 31 33 39; do
  OUT=$O/${TAG}${S}_$SOURCE
  (cd "$SRC" && PYTHONPATH=$SRC/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python "$D/diag.py" "$OUT" \
    counterfactual=true data.root=/tmp/s21data/trees/cf$S output_dir="$OUT/bench" examples=0 threads=1 \
    "counterfactual_kinds=[delete]" "counterfactual_sources=[$SOURCE]" "counterfactual_fills=[rays]" $CK "$@" \
    > "$OUT.log" 2>&1)
  echo "$OUT rc=$?"
done
