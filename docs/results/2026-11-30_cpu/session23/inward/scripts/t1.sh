#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (semantic proposals, then ground-truth masks (oracle)) of the
# code tree CODE (a plain tree of the library), session 21's demo weights (w0, /tmp/s21data/demo/out), by session 11
# semrain's dbench.py (session 21 lead's rows/t1.sh with this helper's paths). De-render caches
# /tmp/s23data/inward/t1/cache<SEED>_<NAME> (one per code: the fit differs); outputs
# /tmp/s23data/inward/t1/<NAME><SEED>_<row>{,.dump,.log}. Trees: /tmp/s21data/trees/t1_<SEED> (TREES to change).
# ROWS: the rows (default "semantic gt").
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s23data/inward/t1; mkdir -p $OUT; WEIGHTS=${WEIGHTS:-/tmp/s21data/demo/out}
TREES=${TREES:-/tmp/s21data/trees}
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  TREE=$TREES/t1_$SEED
  CACHE=$OUT/cache${SEED}_$NAME
  for P in ${ROWS:-semantic gt}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH $CACHE \
       $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' \
       "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
