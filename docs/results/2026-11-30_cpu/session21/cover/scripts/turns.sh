#!/bin/bash
# turns.sh SRC TREE OUT SOURCE: sdn3d-bench's counterfactual turns (photo fill rays) on TREE with the code of SRC (a
# tree with src/), source scene SOURCE (oracle: ground-truth geometry; semantic: predicted, this session's demo
# weights), through capture_turns.py (the whole pictures into OUT.npz); threads 1, nice 5. Writes
# OUT/counterfactual.json, OUT.npz and OUT.log. (Session 19 erase's bench.sh, with the capture and session 21's weights.)
SRC=$1; TREE=$2; OUT=$3; SOURCE=$4
HERE=$(cd "$(dirname "$0")" && pwd)
W=/tmp/s21data/demo/out/runs
CK=""
[ "$SOURCE" = semantic ] && CK="checkpoints.semantic=$W/semantic/checkpoints/inference.pt checkpoints.geometric=$W/geometric/checkpoints/inference.pt"
cd "$SRC" && CAPTURE="$OUT.npz" PYTHONPATH=$SRC/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  "$HERE/capture_turns.py" counterfactual=true data.root="$TREE" output_dir="$OUT" examples=0 threads=1 \
  "counterfactual_kinds=[turn]" "counterfactual_sources=[$SOURCE]" "counterfactual_fills=[rays]" $CK > "$OUT.log" 2>&1
echo "$OUT rc=$?"
