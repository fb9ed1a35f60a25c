#!/bin/bash
# cf.sh CODE NAME TREE...: sdn3d-bench's counterfactual turns (fill rays) with predicted geometry (source semantic,
# session 21's demo weights w0) on each counterfactual TREE, code tree CODE; threads 1, nice 5 (session 21 speck's
# bench.sh with this helper's paths). Writes /tmp/s27data/shape40/cf/<NAME>_<tree name>/counterfactual.json and .log;
# then session 21 speck's paired.py LABEL MAIN_DIR BRANCH_DIR per tree.
CODE=$1; NAME=$2; shift 2; mkdir -p /tmp/s27data/shape40/cf; W=/tmp/s21data/demo/out/runs
for TREE in "$@"; do
  OUT=/tmp/s27data/shape40/cf/${NAME}_$(basename $TREE)
  (cd "$CODE" && PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
    counterfactual=true data.root=$TREE output_dir="$OUT" examples=0 threads=1 "counterfactual_kinds=[turn]" \
    "counterfactual_sources=[semantic]" "counterfactual_fills=[rays]" \
    checkpoints.semantic=$W/semantic/checkpoints/inference.pt checkpoints.geometric=$W/geometric/checkpoints/inference.pt \
    > "$OUT.log" 2>&1)
  echo "$OUT rc=$? $(date -u +%T)"
done
