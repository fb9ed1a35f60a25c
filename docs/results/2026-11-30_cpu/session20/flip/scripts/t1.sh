#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (semantic proposals, then ground-truth masks (oracle)) of the
# code tree CODE, session 11's demo weights, by session 11 semrain's dbench.py: the pattern of session 20 lead's
# rows/t1.sh with this helper's own de-render caches (/tmp/s20data/flip/t1/cache<SEED>_<NAME>: a code whose
# de-render differs gets its own) and outputs /tmp/s20data/flip/t1/<NAME><SEED>_<row>{,.dump,.log}.
# Trees: 35, 37: /tmp/s11data/semrain/t1_<SEED>; 31: /tmp/s11data/lead/t1_31; others /tmp/s20data/flip/t1_<SEED>.
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s20data/flip/t1; mkdir -p $OUT
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  case $SEED in 31) TREE=/tmp/s11data/lead/t1_31;; 35|37) TREE=/tmp/s11data/semrain/t1_$SEED;; *) TREE=/tmp/s20data/flip/t1_$SEED;; esac
  CACHE=$OUT/cache${SEED}_$NAME
  for P in ${ROWS:-semantic gt}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH $CACHE \
       $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[$P]" \
       scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
