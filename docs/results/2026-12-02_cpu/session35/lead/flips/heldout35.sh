#!/bin/bash
# heldout35.sh SEED: generate held-out tree SEED once (refuses if it exists), then the pose table's rows gt_fit and
# pred_fit with weights w35 (this session's demo run of main 9b4abd95) and main's code as it is.
set -u
S=$1; B=/tmp/s35/ho; T=$B/t1_$S; PY=/work/main/.venv/bin/python; W=/tmp/w35/outputs/demo/runs
mkdir -p $B; [ -e $T ] && { echo "exists"; exit 3; }
cd /work/main
echo "gen $S start $(date -u +%T) main $(git rev-parse --short HEAD)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T $S > $B/gen_$S.log 2>&1
echo "gen $S rc=$? $(date -u +%T)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric $W/geometric/checkpoints/inference.pt \
  --semantic $W/semantic/checkpoints/inference.pt --data-root $T --part all --max-frames 40 --threads 1 \
  --image-size 312 96 --rows gt_fit pred_fit --out $B/pose_$S.json > $B/pose_$S.log 2>&1
echo "pose $S rc=$? $(date -u +%T)" >> $B/log.txt
