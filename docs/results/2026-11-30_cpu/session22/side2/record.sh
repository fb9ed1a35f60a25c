#!/bin/bash
# record.sh CODE TREE SOURCE NAME: probe.py (the body examples of every car, $KEYS/$CAPTURE passed on) under
# sdn3d-bench's turn benchmark, fill rays, with the code tree CODE (its src/ on PYTHONPATH), source scene SOURCE
# (oracle: ground-truth geometry; semantic: predicted, session 21's demo weights w0); threads 1, nice 5.
# Writes /tmp/s22data/side2/probe/NAME.pt, NAME.log and the bench output NAME/.
CODE=$1; TREE=$2; SOURCE=$3; NAME=$4; P=/tmp/s22data/side2/probe
HERE=$(cd "$(dirname "$0")" && pwd)
CK=""
[ "$SOURCE" = semantic ] && CK="checkpoints.semantic=/tmp/s21data/demo/out/runs/semantic/checkpoints/inference.pt
 checkpoints.geometric=/tmp/s21data/demo/out/runs/geometric/checkpoints/inference.pt"
cd "$CODE" && RECORD=$P/$NAME.pt PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  "$HERE/probe.py" counterfactual=true data.root="$TREE" output_dir="$P/$NAME" examples=0 threads=1 \
  "counterfactual_kinds=[turn]" "counterfactual_sources=[$SOURCE]" "counterfactual_fills=[rays]" $CK \
  > "$P/$NAME.log" 2>&1
echo "$NAME rc=$?"
