#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (ROWS, default the semantic proposals only; "semantic gt" adds
# the ground-truth-mask (oracle) row) of the code tree CODE (this branch: /work/wt/comp; main of the session's start:
# /tmp/s20data/lead/base_4044), session 11's demo weights, through session 11 semrain's dbench.py, as the lead's
# docs/results/2026-11-30_cpu/session20/lead/rows/t1.sh runs main's rows. Own de-render caches
# $T1_OUT/cache_<NAME><SEED> (the grouping changes the de-render; never the lead's caches);
# outputs $T1_OUT/<NAME><SEED>_<row>{,.dump,.log}; progress in $T1_OUT/t1.log.
# Trees: 35, 37: /tmp/s11data/semrain/t1_<SEED>; 31: /tmp/s11data/lead/t1_31; others $TREES/t1_<SEED>.
# comp2 (the rules' order) runs it with T1_OUT=/tmp/s20data/comp2/t1 TREES=/tmp/s20data/comp2 (defaults: comp's folders).
CODE=$1; NAME=$2; shift 2; OUT=${T1_OUT:-/tmp/s20data/comp/t1}; TREES=${TREES:-/tmp/s20data/comp}; mkdir -p $OUT
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  case $SEED in 31) TREE=/tmp/s11data/lead/t1_31;; 35|37) TREE=/tmp/s11data/semrain/t1_$SEED;; *) TREE=$TREES/t1_$SEED;; esac
  for P in ${ROWS:-semantic}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH \
       $OUT/cache_$NAME$SEED $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s11data/demo/out \
       'compose=[photo]' "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
