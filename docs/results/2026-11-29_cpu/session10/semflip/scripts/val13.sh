#!/bin/bash
# val13 pose table (seed 13 tuning tree, clear weather): base (main f42d17c) and new (this branch), side by side; the
# session-8 command's rows (ground-truth masks + boxes: oracle) plus the semantic proposals' rows (--semantic).
CK=/tmp/s5data/lead/demo/runs/geometric/checkpoints/best-epoch009.ckpt; SEM=/tmp/s5data/lead/demo/runs/semantic/checkpoints/inference.pt
PY=/work/main/.venv/bin/python; O=/tmp/s10data/semflip/val13; export OMP_NUM_THREADS=1
for side in base code_n1; do
  T=/tmp/s10data/semflip/$side
  ( cd $T && PYTHONPATH=$T/src:$T /usr/bin/time -v $PY benchmarks/pose_table.py --geometric $CK --semantic $SEM --data-root /tmp/s3data/val13 --part all --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 --rows gt_branch gt_fit pred_branch pred_fit --crops photo --out $O/$side.json > $O/$side.log 2>&1 ) &
done
wait
