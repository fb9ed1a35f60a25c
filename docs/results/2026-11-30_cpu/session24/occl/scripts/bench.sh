#!/bin/bash
# bench.sh TREE OUT LIMIT: sdn3d-bench (this worktree's code) on a generated Table 1 tree, ground-truth masks
# (oracle) row, photo, 312x96, session 21's demo weights, the first LIMIT entries; stdout+stderr in OUT.log.
#   cd /work/wt/occl && bash docs/results/2026-11-30_cpu/session24/occl/scripts/bench.sh TREE OUT 30
TREE=$1; OUT=$2; LIMIT=$3
cd /work/wt/occl && OMP_NUM_THREADS=1 PYTHONPATH=src nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
  data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s21data/demo/out 'compose=[photo]' 'proposals=[gt]' \
  threads=1 examples=2 limit=$LIMIT output_dir=$OUT overwrite=true > $OUT.log 2>&1
echo "rc=$?" >> $OUT.log
