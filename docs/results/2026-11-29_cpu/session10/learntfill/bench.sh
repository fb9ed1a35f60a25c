#!/bin/bash
# bench.sh TREE OUT WEIGHTS: sdn3d-bench's counterfactual benchmark on TREE's deletes, oracle source scene (ground-truth
# geometry), fills auto (the harness's reference), telea, patchmatch, rays, learnt (photo.learnt_weights=WEIGHTS).
TREE=$1; OUT=$2; W=$3; WT=$(cd "$(dirname "$0")/../../../../.." && pwd)
cd $WT && PYTHONPATH=$WT/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true \
  data.root=$TREE counterfactual_kinds=[delete] counterfactual_fills=[auto,telea,patchmatch,rays,learnt] \
  photo.learnt_weights=$W output_dir=$OUT threads=1 > $OUT.log 2>&1
echo "$TREE rc=$?"
