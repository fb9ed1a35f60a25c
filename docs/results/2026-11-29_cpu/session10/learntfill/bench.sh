#!/bin/bash
# bench.sh TREE OUT FILLS [WEIGHTS]: sdn3d-bench's counterfactual benchmark on TREE's deletes, oracle source scene
# (ground-truth geometry), the photo fills FILLS (e.g. [auto,telea,patchmatch,rays] or [learnt]; learnt with
# photo.learnt_weights=WEIGHTS).
TREE=$1; OUT=$2; FILLS=$3; W=${4:-null}; WT=$(cd "$(dirname "$0")/../../../../.." && pwd)
cd $WT && PYTHONPATH=$WT/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true \
  data.root=$TREE counterfactual_kinds=[delete] counterfactual_fills=$FILLS photo.learnt_weights=$W output_dir=$OUT \
  threads=1 > $OUT.log 2>&1
echo "$TREE $FILLS rc=$?"
