#!/bin/bash
# val13 pose table, final code (code_g = d45d9e3): the semantic proposals' rows (the ground-truth rows' path is unchanged)
CK=/tmp/s5data/lead/demo/runs/geometric/checkpoints/best-epoch009.ckpt; SEM=/tmp/s5data/lead/demo/runs/semantic/checkpoints/inference.pt
PY=/work/main/.venv/bin/python; O=/tmp/s10data/semflip/val13; export OMP_NUM_THREADS=1; T=/tmp/s10data/semflip/code_g
cd $T && PYTHONPATH=$T/src:$T $PY benchmarks/pose_table.py --geometric $CK --semantic $SEM --data-root /tmp/s3data/val13 --part all --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 --rows gt_branch gt_fit pred_branch pred_fit --crops photo --out $O/code_g.json > $O/code_g.log 2>&1
