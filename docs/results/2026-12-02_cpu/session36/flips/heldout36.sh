#!/bin/bash
# heldout36.sh SEED: generate held-out tree SEED once (refuses if it exists) under /tmp/s36f/ho, then rows gt_fit and
# pred_fit with w36: main (a worktree of main, /tmp/s36_main) and LampCue.side_weight = 0.6 (this branch, posevar36.py);
# and main's per-car reading of row gt_fit (cutcars36.py).
set -u
S=$1; B=/tmp/s36f/ho; T=$B/t1_$S; PY=/work/main/.venv/bin/python; W=/tmp/w36/outputs/demo/runs
D=/tmp/s36_flips/docs/results/2026-12-02_cpu/session36/flips
mkdir -p $B; [ -e $T ] && { echo "exists"; exit 3; }
cd /tmp/s36_flips
echo "gen $S start $(date -u +%T) branch $(git rev-parse --short HEAD)" >> $B/log.txt
PYTHONPATH=/tmp/s36_flips/src OMP_NUM_THREADS=1 $PY /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T $S > $B/gen_$S.log 2>&1
echo "gen $S rc=$? $(date -u +%T)" >> $B/log.txt
for v in main sw0.6; do
  LC=""; SRC=/tmp/s36_main/src; [ $v = sw0.6 ] && { LC=side_weight=0.6; SRC=/tmp/s36_flips/src; }
  (cd $SRC/.. && LAMPCUE=$LC PYTHONPATH=$SRC OMP_NUM_THREADS=1 $PY $D/posevar36.py --geometric $W/geometric/checkpoints/inference.pt \
    --semantic $W/semantic/checkpoints/inference.pt --data-root $T --part all --max-frames 40 --threads 1 \
    --image-size 312 96 --rows gt_fit pred_fit --out $B/${v}_$S.json > $B/${v}_$S.log 2>&1)
  echo "$v $S rc=$? $(date -u +%T)" >> $B/log.txt
done
PYTHONPATH=/tmp/s36_main/src OMP_NUM_THREADS=1 $PY $D/cutcars36.py $T $W $B/cut_$S.json 312 96 > $B/cut_$S.log 2>&1
echo "cut $S rc=$? $(date -u +%T)" >> $B/log.txt
