#!/bin/bash
# held.sh: session 21 hidden's held-out measurement, run once after the code was final (bash held.sh from anywhere):
# generate Table 1 tree 2187 (session 9 fogflip's gen_t1.py) into /tmp/s21data/hidden/t1_2187; main's
# (/tmp/s21data/lead/base_ea2) and the branch's (/work/wt/hidden) Table 1 rows on it (semantic proposals and
# ground-truth masks (oracle), t1.sh, the two arms side by side); the network's raw outputs on its source frames
# (raw.py); proposal recall, merged proposals and mean best IoU (recall.py: main = stray_distance None, the branch's
# defaults); the Table 1 operations that pick a merged proposal in each arm (picks.py); the paired intervals (session
# 18 pick's compare.py). Tables: ../tables/heldout_*.
set -u
cd /work/wt/hidden
R=docs/results/2026-11-30_cpu/session21/hidden; S=$R/scripts; T=$R/tables; OUT=/tmp/s21data/hidden; SEED=2187
PY="nice -n 5 /work/main/.venv/bin/python"; export PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1
export T1_OUT=$OUT/t1 TREES=$OUT
echo "gen start $(date -u +%T)" >> $T1_OUT/t1.log
$PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $OUT/t1_$SEED $SEED > $OUT/gen$SEED.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $T1_OUT/t1.log
ROWS="semantic gt" bash $S/t1.sh /tmp/s21data/lead/base_ea2 main $SEED &
ROWS="semantic gt" bash $S/t1.sh /work/wt/hidden hid $SEED &
wait
$PY $S/raw.py $OUT/t1_$SEED 312 96 $OUT/raw${SEED}_312.pt > $OUT/raw$SEED.log 2>&1
$PY $S/recall.py $OUT/raw${SEED}_312.pt > $T/heldout_recall.txt 2>&1
for A in main hid; do
  $PY $S/picks.py $T1_OUT/${A}${SEED}_semantic.dump $OUT/raw${SEED}_312.pt > $T/heldout_picks_$A.txt 2>&1
done
$PY $S/compare.py "held-out $SEED semantic proposals (312x96, photo)" \
  $T1_OUT/main${SEED}_semantic:$T1_OUT/hid${SEED}_semantic > $T/heldout_compare_semantic.txt 2>&1
$PY $S/compare.py "held-out $SEED ground-truth masks (oracle)" \
  $T1_OUT/main${SEED}_gt:$T1_OUT/hid${SEED}_gt > $T/heldout_compare_gt.txt 2>&1
echo "held done $(date -u +%T)" >> $T1_OUT/t1.log
