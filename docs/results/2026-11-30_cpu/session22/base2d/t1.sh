#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (semantic proposals and ground-truth masks (oracle), the two
# rows side by side, 2 processes) of the code tree CODE, the demo weights w0 (/tmp/s21data/demo/out, seed 0), by
# session 11 semrain's dbench.py (session 21 lead's rows/t1.sh with this helper's paths). De-render caches
# /tmp/s22data/base2d/t1/cache<SEED> (the tuning trees' copied from session 22 occl's, the same for both codes, so
# every pair reads the same source scenes); outputs /tmp/s22data/base2d/t1/<NAME><SEED>_<row>{,.dump,.log}.
# Trees: /tmp/s21data/trees/t1_<SEED>, else /tmp/s22data/base2d/trees/t1_<SEED> (the held-out one).
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s22data/base2d/t1; mkdir -p $OUT; WEIGHTS=${WEIGHTS:-/tmp/s21data/demo/out}
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  TREE=/tmp/s21data/trees/t1_$SEED
  [ -d "$TREE" ] || TREE=/tmp/s22data/base2d/trees/t1_$SEED
  CACHE=$OUT/cache$SEED
  for P in ${ROWS:-semantic gt}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH $CACHE \
       $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' \
       "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1
     echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log) &
  done
  wait
done
