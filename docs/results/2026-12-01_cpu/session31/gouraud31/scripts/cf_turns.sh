#!/bin/bash
# cf_turns.sh SRC TREE OUT SOURCE [OVERRIDE ...]: sdn3d-bench's counterfactual turn pairs (kinds [turn], photo fill
# rays) on TREE with the code of the plain tree SRC, source scene SOURCE (oracle: ground-truth geometry; semantic:
# predicted with session 30 lead demo weights w31), threads 1, nice 5. Writes OUT/counterfactual.json and OUT.log.
# (session 27 shadow41's cf_bench.sh with the turn kind; session 30 gouraud30's, weights w31.)
SRC=$1; TREE=$2; OUT=$3; SOURCE=$4
W=/tmp/s31/ci/outputs/demo/runs
CK=""
[ "$SOURCE" = semantic ] && CK="checkpoints.semantic=$W/semantic/checkpoints/inference.pt checkpoints.geometric=$W/geometric/checkpoints/inference.pt"
cd "$SRC" && PYTHONPATH=$SRC/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
  counterfactual=true data.root="$TREE" output_dir="$OUT" examples=0 threads=1 "counterfactual_kinds=[turn]" \
  "counterfactual_sources=[$SOURCE]" "counterfactual_fills=[rays]" $CK "${@:5}" > "$OUT.log" 2>&1
echo "$OUT rc=$? $(date -u +%T)"
