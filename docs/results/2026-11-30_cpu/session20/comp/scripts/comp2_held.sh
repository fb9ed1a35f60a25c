#!/bin/bash
# comp2_held.sh: comp2's held-out measurement (the split first, then the part rule), run once after the code was
# final: generate Table 1 tree 2181 into /tmp/s20data/comp2, main's (/tmp/s20data/lead/base_4044) and comp2's
# (/work/wt/comp2) Table 1 rows on it (semantic proposals and ground-truth masks (oracle), t1.sh with comp2's folders),
# the network's raw outputs on its source frames (session 19 inst's raw.py), proposal recall (recall.py: the floor,
# main's grouping, comp2's defaults), the cars whose IoU crosses 0.5 or 0.3 (carwise.py), comp's order against comp2's
# (order_diff.py e6337c1), and the paired intervals (session 18 pick's compare.py). Tables: tables/comp2_heldout_*.
set -u
cd /work/wt/comp2
R=docs/results/2026-11-30_cpu/session20/comp; S=$R/scripts; T=$R/tables; OUT=/tmp/s20data/comp2; SEED=2181
PY="nice -n 5 /work/main/.venv/bin/python"; export PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1
export T1_OUT=$OUT/t1 TREES=$OUT; mkdir -p $T1_OUT
echo "gen start $(date -u +%T)" >> $T1_OUT/t1.log
$PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $OUT/t1_$SEED $SEED > $OUT/gen$SEED.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $T1_OUT/t1.log
ROWS="semantic gt" bash $S/t1.sh /tmp/s20data/lead/base_4044 main $SEED
ROWS="semantic gt" bash $S/t1.sh /work/wt/comp2 comp2_ $SEED
$PY docs/results/2026-11-30_cpu/session19/inst/scripts/raw.py $OUT/t1_$SEED 312 96 $OUT/raw${SEED}_312.pt > $OUT/raw$SEED.log 2>&1
ARMS='{"components": null, "main": {"part_separation": null}, "comp2": {}}' $PY $S/recall.py $OUT/raw${SEED}_312.pt > $T/comp2_heldout_recall.txt 2>&1
$PY $S/carwise.py $OUT/raw${SEED}_312.pt > $T/comp2_heldout_carwise.txt 2>&1
$PY $S/order_diff.py e6337c1 $OUT/raw${SEED}_312.pt > $T/comp2_heldout_order_diff.txt 2>&1
$PY docs/results/2026-11-30_cpu/session18/pick/scripts/compare.py "held-out $SEED semantic proposals (312x96, photo)" \
  $T1_OUT/main${SEED}_semantic:$T1_OUT/comp2_${SEED}_semantic > $T/comp2_heldout_compare_semantic.txt 2>&1
$PY docs/results/2026-11-30_cpu/session18/pick/scripts/compare.py "held-out $SEED ground-truth masks (oracle)" \
  $T1_OUT/main${SEED}_gt:$T1_OUT/comp2_${SEED}_gt > $T/comp2_heldout_compare_gt.txt 2>&1
echo "held done $(date -u +%T)" >> $T1_OUT/t1.log
