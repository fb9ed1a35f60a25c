#!/bin/bash
# heldout.sh SEED: generate held-out tree SEED once, then gt_fit (cutcars) main vs change, pred_fit main vs change.
set -u
S=$1; B=/tmp/s34/ho; T=$B/t1_$S; PY=/work/main/.venv/bin/python; W=/tmp/s34/demo/outputs/demo/runs
mkdir -p $B; [ -e $T ] && { echo "exists"; exit 3; }
cd /work/main
echo "gen $S start $(date -u +%T)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T $S > $B/gen_$S.log 2>&1
echo "gen $S rc=$? $(date -u +%T)" >> $B/log.txt
for v in main change; do
  PP=; [ $v = main ] && PP=/tmp/s34/mainsrc/src
  PYTHONPATH=$PP OMP_NUM_THREADS=1 $PY /work/notes/s34/flips/cutcars.py $T $W $B/gt_${v}_$S.json 312 96 > $B/gt_${v}_$S.log 2>&1
  echo "gt $v $S rc=$? $(date -u +%T)" >> $B/log.txt
  PYTHONPATH=$PP OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric $W/geometric/checkpoints/inference.pt \
    --semantic $W/semantic/checkpoints/inference.pt --data-root $T --part all --max-frames 40 --threads 1 \
    --image-size 312 96 --rows pred_fit --out $B/pred_${v}_$S.json > $B/pred_${v}_$S.log 2>&1
  echo "pred $v $S rc=$? $(date -u +%T)" >> $B/log.txt
done
