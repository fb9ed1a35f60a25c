#!/usr/bin/env bash
# run.sh SEED: generate held-out tree SEED once (session 9's gen_t1.py; refuses if it exists), then the pose table's
# gt_fit and pred_fit rows on it (40 frames, all parts, 312x96, one thread) with weights w37, code main at this
# session's start (/tmp/s37_base: the fit is unchanged since). Output /tmp/s37/flips/SEED.json.
set -u
SEED=$1; F=/tmp/s37/flips; TREE=$F/trees/t1_$SEED; CODE=/tmp/s37_base; W=/tmp/w37/outputs/demo/runs; mkdir -p $F/trees
[ -e "$TREE" ] && { echo "tree $TREE exists: one generation only" >&2; exit 3; }
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1
(cd $CODE && /work/main/.venv/bin/python /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE $SEED > $F/gen_$SEED.log 2>&1)
echo "$SEED gen rc=$? $(date -u +%T)" >> $F/run.log
(cd /work/main && /work/main/.venv/bin/python benchmarks/pose_table.py --geometric $W/geometric/checkpoints/inference.pt \
   --semantic $W/semantic/checkpoints/inference.pt --data-root $TREE --part all --max-frames 40 --threads 1 \
   --image-size 312 96 --rows gt_fit pred_fit --out $F/$SEED.json > $F/$SEED.log 2>&1)
echo "$SEED pose rc=$? $(date -u +%T)" >> $F/run.log
