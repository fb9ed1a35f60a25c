#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (ROWS, default the semantic proposals only; "semantic gt" adds
# the ground-truth-mask (oracle) row) of the code tree CODE (this branch: /work/wt/hidden; main of the session's start:
# /tmp/s21data/lead/base_ea2), session 21's demo weights (/tmp/s21data/demo/out), through session 11 semrain's
# dbench.py (session 20 comp's t1.sh with session 21's folders). Own de-render caches $T1_OUT/cache_<NAME><SEED> (the
# grouping changes the de-render); outputs $T1_OUT/<NAME><SEED>_<row>{,.dump,.log}; progress in $T1_OUT/t1.log.
# Trees: $TREES/t1_<SEED> (default /tmp/s21data/trees). Run: bash t1.sh /work/wt/hidden hid 35 37 31
CODE=$1; NAME=$2; shift 2; OUT=${T1_OUT:-/tmp/s21data/hidden/t1}; TREES=${TREES:-/tmp/s21data/trees}; mkdir -p $OUT
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  TREE=$TREES/t1_$SEED
  for P in ${ROWS:-semantic}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH \
       $OUT/cache_$NAME$SEED $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s21data/demo/out \
       'compose=[photo]' "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
