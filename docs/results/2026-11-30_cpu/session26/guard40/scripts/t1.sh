#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (semantic proposals, then ground-truth masks (oracle)) of the
# code tree CODE (a git archive), this session's demo weights (/tmp/s21data/demo/out, seed 0), by session 11
# semrain's dbench.py (session 20 lead's rows/t1.sh with session 21 paths). De-render caches
# $T1OUT (default /tmp/s26data/guard40/t1)/cache<SEED><CACHE_TAG>; outputs $T1OUT (default /tmp/s26data/guard40/t1)/<NAME><SEED>_<row>{,.dump,.log}.
# Trees: $TREES/t1_<SEED> (default /tmp/s21data/trees). CACHE_TAG: a suffix of the cache folder, for a code or weights whose
# de-render differs. WEIGHTS: another training run (default the demo run of the session start, seed 0).
CODE=$1; NAME=$2; shift 2; OUT=${T1OUT:-/tmp/s26data/guard40/t1}; mkdir -p $OUT; WEIGHTS=${WEIGHTS:-/tmp/s21data/demo/out}
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  TREE=${TREES:-/tmp/s21data/trees}/t1_$SEED
  CACHE=$OUT/cache$SEED${CACHE_TAG:-}
  for P in ${ROWS:-semantic gt}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH $CACHE \
       $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' \
       "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
