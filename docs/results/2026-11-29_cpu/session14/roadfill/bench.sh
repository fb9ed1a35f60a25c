#!/bin/bash
# bench.sh SRC TREE OUT SOURCE FILLS [OVERRIDE ...]: sdn3d-bench's counterfactual benchmark on TREE's deletes with the code of SRC (a
# checkout), source scene SOURCE (oracle: ground-truth geometry; semantic: predicted proposals of the session 11 demo's
# branches), photo fills FILLS (e.g. [telea,patchmatch,rays,learnt]), further sdn3d-bench overrides (e.g.
# +photo.ray_verge=road); threads 1, nice 5. OUT/counterfactual.json.
SRC=$1; TREE=$2; OUT=$3; SOURCE=$4; FILLS=$5
CK=""
[ "$SOURCE" = semantic ] && CK="checkpoints.semantic=/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s11data/demo/out/runs/geometric/checkpoints/inference.pt"
cd "$SRC" && PYTHONPATH=$SRC/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
  counterfactual=true data.root="$TREE" output_dir="$OUT" examples=0 threads=1 'counterfactual_kinds=[delete]' \
  "counterfactual_sources=[$SOURCE]" "counterfactual_fills=$FILLS" $CK "${@:6}" > "$OUT.log" 2>&1
echo "$OUT rc=$?"
