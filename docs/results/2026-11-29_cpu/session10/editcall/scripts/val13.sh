#!/bin/bash
# val13 pose table (seed 13 tuning tree; oracle: ground-truth masks and ground-truth boxes), fit row, before (base = f42d17c,
# a git archive) and after (TREE, default this worktree: FitSettings.parts=2), side by side, threads 1.
CK=/tmp/s5data/lead/demo/runs/geometric/checkpoints/best-epoch009.ckpt; PY=/work/main/.venv/bin/python
O=${O:-/tmp/s10data/editcall/val13}; DATA=${DATA:-/tmp/s3data/val13}; export OMP_NUM_THREADS=1; mkdir -p $O
uptime
for side in base new; do
  T=/tmp/s10data/editcall/base; [ $side = new ] && T=${TREE:-/work/wt/editcall}
  ( cd $T && PYTHONPATH=$T/src:$T /usr/bin/time -v $PY benchmarks/pose_table.py --geometric $CK --data-root $DATA --part all --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 --rows gt_branch gt_fit --crops photo --out $O/$side.json > $O/$side.log 2>&1 ) &
done
wait
uptime
