#!/bin/bash
# var.sh TAG LAMPCUE SEEDS...: rows gt_fit + pred_fit with w36 on the tuning trees /tmp/s36/t1_SEED (read only),
# SRC (default /tmp/s36_flips/src): the package to run (main: a worktree of main); the LampCue fields of LAMPCUE
# set (posevar36.py; "" = as the code is); outputs /tmp/s36f/tune/TAG_SEED.json.
set -u
TAG=$1; LC=$2; shift 2
D=/tmp/s36_flips/docs/results/2026-12-02_cpu/session36/flips; W=/tmp/w36/outputs/demo/runs; O=/tmp/s36f/tune
cd ${SRC:-/tmp/s36_flips/src}/..
for S in "$@"; do
  LAMPCUE=$LC PYTHONPATH=${SRC:-/tmp/s36_flips/src} OMP_NUM_THREADS=1 /work/main/.venv/bin/python $D/posevar36.py \
    --geometric $W/geometric/checkpoints/inference.pt --semantic $W/semantic/checkpoints/inference.pt \
    --data-root /tmp/s36/t1_$S --part all --max-frames 40 --threads 1 --image-size 312 96 --rows gt_fit pred_fit \
    --out $O/${TAG}_$S.json > $O/${TAG}_$S.log 2>&1
  echo "$TAG $S rc=$? $(date -u +%T)" >> $O/log.txt
done
