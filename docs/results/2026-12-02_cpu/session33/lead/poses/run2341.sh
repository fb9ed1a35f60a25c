#!/bin/bash
# run2341.sh: held-out Table 1 tree 2341 (gen_t1.py's recipe; generated once: refuses if it exists), then
# benchmarks/pose_table.py on every frame of it (--part all: no run trained on it), w33, one thread.
set -u
B=/tmp/s33/poses; TREE=$B/t1_2341; PY=/work/main/.venv/bin/python; W=/tmp/s33/democlone/outputs/demo/runs
[ -e "$TREE" ] && { echo "tree $TREE exists: one generation only" >&2; exit 3; }
mkdir -p $B; cd /work/main
echo "gen start $(date -u +%T)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE 2341 > $B/gen.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric $W/geometric/checkpoints/inference.pt \
  --semantic $W/semantic/checkpoints/inference.pt --data-root $TREE --part all --max-frames 40 --threads 1 \
  --image-size 312 96 --rows gt_branch gt_fit boxes_fit pred_branch pred_fit --out $B/pose_2341.json > $B/pose.log 2>&1
echo "pose rc=$? $(date -u +%T)" >> $B/log.txt
