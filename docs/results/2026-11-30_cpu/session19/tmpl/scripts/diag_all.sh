#!/bin/bash
# diag_all.sh TAG [SETTINGS]: diag.py on session 18 tierule's captures of the tuning trees 35, 37, 31 (semantic proposals and
# ground-truth masks (oracle)), FitSettings NAME=VALUE[+...] (e.g. template_size=stands_for); outputs in /tmp/s19data/tmpl/diag/
CODE=/work/wt/tmpl; TAG=$1; SET=$2; OUT=/tmp/s19data/tmpl/diag; mkdir -p $OUT
for SEED in 35 37 31; do
  [ $SEED = 31 ] && TREE=/tmp/s11data/lead/t1_31 || TREE=/tmp/s11data/semrain/t1_$SEED
  for P in semantic gt; do
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python docs/results/2026-11-30_cpu/session19/tmpl/scripts/diag.py \
      $TREE /tmp/s18data/tierule/cap/${P}$SEED $OUT/${P}${SEED}_$TAG.json $SET > $OUT/${P}${SEED}_$TAG.log 2>&1)
    echo "diag $TAG $SEED $P rc=$? $(date -u +%T)" >> $OUT/done.log
  done
done
