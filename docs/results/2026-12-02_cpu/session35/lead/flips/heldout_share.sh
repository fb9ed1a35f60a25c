#!/bin/bash
# heldout_share.sh SEED: generate held-out tree SEED once (refuses if it exists), then rows gt_fit and pred_fit with w35,
# main as it is and with LampCue.white_min_share = 0.005 (posevar35.py).
set -u
S=$1; B=/tmp/s35/ho2; T=$B/t1_$S; PY=/work/main/.venv/bin/python; W=/tmp/w35/outputs/demo/runs
D=/work/main/docs/results/2026-12-02_cpu/session35/lead/flips
mkdir -p $B; [ -e $T ] && { echo "exists"; exit 3; }
cd /work/main
echo "gen $S start $(date -u +%T) main $(git rev-parse --short HEAD)" >> $B/log.txt
OMP_NUM_THREADS=1 $PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T $S > $B/gen_$S.log 2>&1
echo "gen $S rc=$? $(date -u +%T)" >> $B/log.txt
for v in main share5; do
  LC=""; [ $v = share5 ] && LC=white_min_share=0.005
  LAMPCUE=$LC OMP_NUM_THREADS=1 $PY $D/posevar35.py --geometric $W/geometric/checkpoints/inference.pt \
    --semantic $W/semantic/checkpoints/inference.pt --data-root $T --part all --max-frames 40 --threads 1 \
    --image-size 312 96 --rows gt_fit pred_fit --out $B/${v}_$S.json > $B/${v}_$S.log 2>&1
  echo "$v $S rc=$? $(date -u +%T)" >> $B/log.txt
done
