#!/bin/bash
# held.sh: the held-out measurement, run once after the code was final (06ec323): generate Table 1 tree 2177, then
# main's (/tmp/s20data/lead/base_4044) and this branch's Table 1 rows on it (semantic proposals and ground-truth masks
# (oracle), t1.sh), the branch's raw outputs on its source frames (session 19 inst's raw.py) and proposal recall
# (recall.py: main's grouping = part_separation None, the branch's defaults, the components floor), the paired
# intervals (session 18 pick's compare.py). Tables under the records' tables/heldout_*.
set -u
cd /work/wt/comp
R=docs/results/2026-11-30_cpu/session20/comp; S=$R/scripts; T=$R/tables; OUT=/tmp/s20data/comp
PY="nice -n 5 /work/main/.venv/bin/python"; export PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1
echo "gen start $(date -u +%T)" >> $OUT/t1/t1.log
$PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $OUT/t1_2177 2177 > $OUT/gen2177.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $OUT/t1/t1.log
ROWS="semantic gt" $S/t1.sh /tmp/s20data/lead/base_4044 main 2177
ROWS="semantic gt" $S/t1.sh /work/wt/comp comp 2177
$PY docs/results/2026-11-30_cpu/session19/inst/scripts/raw.py $OUT/t1_2177 312 96 $OUT/raw2177_312.pt > $OUT/raw2177.log 2>&1
$PY $S/recall.py $OUT/raw2177_312.pt > $T/heldout_recall.txt 2>&1
$PY $S/parts.py $OUT/raw2177_312.pt > $T/heldout_parts_branch.txt 2>&1
GROUPING='{"part_separation": null}' $PY $S/parts.py $OUT/raw2177_312.pt > $T/heldout_parts_main.txt 2>&1
$PY docs/results/2026-11-30_cpu/session18/pick/scripts/compare.py "held-out 2177 semantic proposals (312x96, photo)" \
  $OUT/t1/main2177_semantic:$OUT/t1/comp2177_semantic > $T/heldout_compare_semantic.txt 2>&1
$PY docs/results/2026-11-30_cpu/session18/pick/scripts/compare.py "held-out 2177 ground-truth masks (oracle)" \
  $OUT/t1/main2177_gt:$OUT/t1/comp2177_gt > $T/heldout_compare_gt.txt 2>&1
echo "held done $(date -u +%T)" >> $OUT/t1/t1.log
