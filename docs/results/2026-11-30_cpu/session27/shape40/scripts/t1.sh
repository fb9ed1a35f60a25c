#!/bin/bash
# t1.sh CODE NAME TREE...: Table 1 photo rows at 312x96 (semantic proposals, then ground-truth masks (oracle)) of the
# code tree CODE, session 21's demo weights (w0, /tmp/s21data/demo/out), by session 11 semrain's dbench.py (session
# 25 lead's t1.sh with this helper's paths). De-render caches /tmp/s27data/shape40/t1/cache_<NAME>_<tree name>;
# outputs /tmp/s27data/shape40/t1/<NAME>_<tree name>_<row>{,.dump,.log}. env ROWS (default: semantic gt).
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s27data/shape40/t1; mkdir -p $OUT; WEIGHTS=${WEIGHTS:-/tmp/s21data/demo/out}
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for TREE in "$@"; do
  T=$(basename $TREE)
  for P in ${ROWS:-semantic gt}; do
    RUN=$OUT/${NAME}_${T}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH \
       $OUT/cache_${NAME}_$T $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' \
       "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $T $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
