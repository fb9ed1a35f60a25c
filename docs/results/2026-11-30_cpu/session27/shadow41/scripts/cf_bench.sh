#!/bin/bash
# bench.sh SRC TREE OUT SOURCE FILLS KINDS [OVERRIDE ...]: sdn3d-bench's counterfactual benchmark on TREE with the code
# of SRC (a git archive), source scene SOURCE (oracle: ground-truth geometry; semantic: predicted, this session's demo
# semantic and geometric weights, /tmp/s21data/demo), photo fills FILLS (e.g. [telea,patchmatch,rays,learnt]), pair kinds KINDS ([delete]
# or [turn]), further sdn3d-bench overrides; threads 1, nice 5. Writes OUT/counterfactual.json and OUT.log. (Session
# 21 speck's bench.sh, unchanged; the environment passes through, e.g. ABL= for the ablation tree.)
SRC=$1; TREE=$2; OUT=$3; SOURCE=$4; FILLS=$5; KINDS=$6
CK=""
[ "$SOURCE" = semantic ] && CK="checkpoints.semantic=/tmp/s21data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s21data/demo/out/runs/geometric/checkpoints/inference.pt"
cd "$SRC" && PYTHONPATH=$SRC/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
  counterfactual=true data.root="$TREE" output_dir="$OUT" examples=0 threads=1 "counterfactual_kinds=$KINDS" \
  "counterfactual_sources=[$SOURCE]" "counterfactual_fills=$FILLS" $CK "${@:7}" > "$OUT.log" 2>&1
echo "$OUT rc=$?"
