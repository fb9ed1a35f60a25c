#!/bin/bash
# heldout.sh: pose tables of both arms on held-out 2429 (40 frames) and 2431 (80 frames), side by side, one thread each.
# main arm: worktree of b406c7b1 (/work/wt_base); sharp arm: /work/main's working tree (the change).
W=/tmp/w39/outputs/demo/runs; G=$W/geometric/checkpoints/inference.pt; S=$W/semantic/checkpoints/inference.pt
run() { arm=$1; code=$2; tree=$3; fr=$4; rows=$5
  OMP_NUM_THREADS=1 PYTHONPATH=$code/src /work/main/.venv/bin/python /work/main/benchmarks/pose_table.py --geometric $G --semantic $S \
    --data-root /tmp/trees/$tree --part all --max-frames $fr --threads 1 --image-size 312 96 --rows $rows \
    --out /tmp/s39h/pose_${tree}_$arm.json > /tmp/s39h/pose_${tree}_$arm.log 2>&1; echo "$arm $tree rc=$?"; }
run main /work/wt_base h2429 40 "gt_fit boxes_fit pred_fit" & run sharp /work/main h2429 40 "gt_fit boxes_fit pred_fit" & wait
run main /work/wt_base h2431 80 "gt_fit boxes_fit" & run sharp /work/main h2431 80 "gt_fit boxes_fit" & wait
