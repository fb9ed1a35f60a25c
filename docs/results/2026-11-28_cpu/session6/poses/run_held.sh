#!/bin/bash
# held-out 2071, once: variant $1 (image|photo): gt rows, then boxes and predicted proposals rows
cd /work/wt/s6-poses
CK=/tmp/s5data/lead/demo/runs/geometric/checkpoints/best-epoch009.ckpt
SEM=/tmp/s5data/lead/demo/runs/semantic/checkpoints/best-epoch013.ckpt
run() {  # rows tag
  PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python benchmarks/pose_table.py --geometric $CK --semantic $SEM \
    --data-root /tmp/s6data/poses/pose2071 --part all --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 \
    --rows $1 --crops $3 --out /tmp/s6data/poses/h2071_$2_$3.json > /tmp/s6data/poses/h2071_$2_$3.log 2>&1
}
run "gt_branch gt_fit" gt $1
run "boxes_branch boxes_fit pred_branch pred_fit" bp $1
