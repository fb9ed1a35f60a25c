#!/bin/bash
# t1.sh CODE NAME ROWS SEED...: Table 1 photo rows at 312x96 (ROWS: "semantic gt", i.e. semantic proposals and/or
# ground-truth masks (oracle)), session 11's demo weights, fit_proposals on (the bench default), by session 11
# semrain's dbench.py (the pattern of session 17 lead's rows/t1.sh); tuning trees 35, 37 (semrain), 31 (lead), else
# /tmp/s18data/tierule/t1_SEED; de-renders cached per code and seed, outputs in /tmp/s18data/tierule/t1/.
CODE=$1; NAME=$2; ROWS=$3; shift 3; OUT=/tmp/s18data/tierule/t1
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  case $SEED in 31) TREE=/tmp/s11data/lead/t1_31;; 35|37) TREE=/tmp/s11data/semrain/t1_$SEED;;
    *) TREE=/tmp/s18data/tierule/t1_$SEED;; esac
  for P in $ROWS; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH \
       $OUT/cache_$NAME$SEED $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s11data/demo/out \
       'compose=[photo]' "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
