#!/bin/bash
# t1.sh CODE NAME CACHE_PREFIX SEED...: Table 1 photo rows at 312x96 (semantic proposals, then ground-truth masks
# (oracle)), session 11's demo weights, on the tuning trees of session 11 (t1_35, t1_37: semrain; t1_31: lead), by
# session 11 semrain's dbench.py; de-renders cached in CACHE_PREFIX<SEED>; outputs in /tmp/s17data/lead/t1/.
CODE=$1; NAME=$2; CACHE=$3; shift 3; OUT=/tmp/s17data/lead/t1
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  [ $SEED = 31 ] && TREE=/tmp/s11data/lead/t1_31 || TREE=/tmp/s11data/semrain/t1_$SEED
  for P in semantic gt; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH $CACHE$SEED \
       $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[$P]" \
       scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
