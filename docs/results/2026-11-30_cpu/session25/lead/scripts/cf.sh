#!/bin/bash
# cf.sh CODE NAME SOURCE: sdn3d-bench's counterfactual benchmark (turns and deletes, fill rays) on the tree
# /tmp/s25data/lead/trees/cf2243 with the code tree CODE (a git archive), source scene SOURCE (oracle: ground-truth
# geometry; semantic: predicted, session 21's demo weights w0); threads 1, nice 5 (session 21 speck's bench.sh with
# session 25 paths). Writes /tmp/s25data/lead/cf/<NAME>_<SOURCE>/counterfactual.json and .log; then
# session 21 speck's paired.py LABEL MAIN_DIR BRANCH_DIR.
CODE=$1; NAME=$2; SOURCE=$3; OUT=/tmp/s25data/lead/cf/${NAME}_$SOURCE; mkdir -p /tmp/s25data/lead/cf
W=/tmp/s21data/demo/out/runs
CK=""
[ "$SOURCE" = semantic ] && CK="checkpoints.semantic=$W/semantic/checkpoints/inference.pt checkpoints.geometric=$W/geometric/checkpoints/inference.pt"
cd "$CODE" && PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
  counterfactual=true data.root=/tmp/s25data/lead/trees/cf2243 output_dir="$OUT" examples=0 threads=1 \
  "counterfactual_kinds=[turn,delete]" "counterfactual_sources=[$SOURCE]" "counterfactual_fills=[rays]" $CK \
  > "$OUT.log" 2>&1
echo "$OUT rc=$? $(date -u +%T)"
