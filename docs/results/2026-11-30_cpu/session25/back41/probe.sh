#!/bin/bash
# probe.sh SRC TREE OUT SOURCE: probe.py (sdn3d-bench's counterfactual turn benchmark, fill rays, with the error by
# source code and part recorded) on TREE with the code of SRC, source scene SOURCE (oracle: ground-truth geometry;
# semantic: predicted, session 21's demo weights w0, /tmp/s21data/demo/out); threads 1, nice 5.
# Writes OUT/counterfactual.json, OUT.pt (probe.py's record) and OUT.log.
SRC=$1; TREE=$2; OUT=$3; SOURCE=$4
HERE=$(cd "$(dirname "$0")" && pwd)
CK=""
[ "$SOURCE" = semantic ] && CK="checkpoints.semantic=/tmp/s21data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s21data/demo/out/runs/geometric/checkpoints/inference.pt"
cd "$SRC" && RECORD="$OUT.pt" PYTHONPATH=$SRC/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  "$HERE/probe.py" counterfactual=true data.root="$TREE" output_dir="$OUT" examples=0 threads=1 \
  "counterfactual_kinds=[turn]" "counterfactual_sources=[$SOURCE]" "counterfactual_fills=[rays]" $CK > "$OUT.log" 2>&1
echo "$OUT rc=$?"
