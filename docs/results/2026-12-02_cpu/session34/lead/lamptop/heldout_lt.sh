#!/bin/bash
# heldout_lt.sh SEED: generate held-out tree SEED once, then rows gt_fit + pred_fit with lamp_top 0 (main) and 0.3.
set -u
S=$1; B=/tmp/s34/ho2; T=$B/t1_$S; PY=/work/main/.venv/bin/python; W=/tmp/s34/demo/outputs/demo/runs
mkdir -p $B; [ -e $T ] && { echo "exists"; exit 3; }
cd /work/main
echo "gen $S start $(date -u +%T)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T $S > $B/gen_$S.log 2>&1
echo "gen $S rc=$? $(date -u +%T)" >> $B/log.txt
for v in 0 0.3; do
  LAMPCUE=lamp_top=$v OMP_NUM_THREADS=1 $PY /work/notes/s34/flips/posevar.py --geometric $W/geometric/checkpoints/inference.pt \
    --semantic $W/semantic/checkpoints/inference.pt --data-root $T --part all --max-frames 40 --threads 1 \
    --image-size 312 96 --rows gt_fit pred_fit --out $B/lt${v}_$S.json > $B/lt${v}_$S.log 2>&1
  echo "lt $v $S rc=$? $(date -u +%T)" >> $B/log.txt
done
