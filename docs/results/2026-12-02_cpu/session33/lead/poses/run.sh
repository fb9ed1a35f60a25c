#!/bin/bash
# run.sh SEED [W H]: held-out Table 1 tree SEED (gen_t1.py's recipe; generated once: refuses if it exists), then
# benchmarks/pose_table.py on every frame of it (--part all: no run trained on it), w33, one thread; W H: the working
# size (--image-size; none: the tool's default, the tree's stored size). Run as `run.sh 2339` and `run.sh 2341 312 96`
# (the session ran them as two copies of this script, run2339.sh and run2341.sh, with the seed and size written in).
set -u
SEED=$1; shift; SIZE=(); [ $# -eq 2 ] && SIZE=(--image-size "$1" "$2")
B=/tmp/s33/poses; TREE=$B/t1_$SEED; PY=/work/main/.venv/bin/python; W=/tmp/s33/democlone/outputs/demo/runs
[ -e "$TREE" ] && { echo "tree $TREE exists: one generation only" >&2; exit 3; }
mkdir -p $B; cd /work/main
echo "gen start $(date -u +%T)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE $SEED > $B/gen.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric $W/geometric/checkpoints/inference.pt \
  --semantic $W/semantic/checkpoints/inference.pt --data-root $TREE --part all --max-frames 40 --threads 1 \
  "${SIZE[@]}" --rows gt_branch gt_fit boxes_fit pred_branch pred_fit --out $B/pose_$SEED.json > $B/pose.log 2>&1
echo "pose rc=$? $(date -u +%T)" >> $B/log.txt
