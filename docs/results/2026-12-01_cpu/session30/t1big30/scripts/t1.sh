#!/bin/bash
# t1.sh SEED ROW: one Table 1 photo row at 312x96 of the plain tree of main (/tmp/s30/t1big30/base), weights w30
# (/tmp/s30/demo/outputs/demo), every entry, by session 11 semrain's dbench.py (copied here: sdn3d-bench with the
# de-rendered source scenes cached and each entry's pictures dumped). ROW: semantic (predicted) or gt (oracle).
# Adapted from session 28 merge40's t1.sh. Outputs /tmp/s30/t1big30/t1/<SEED>_<ROW>{,.dump,.log}, wall time in t1.log.
SEED=$1; P=$2; OUT=/tmp/s30/t1big30/t1; mkdir -p $OUT; WEIGHTS=${WEIGHTS:-/tmp/s30/demo/outputs/demo}
CODE=/tmp/s30/t1big30/base; TREE=/tmp/s30/t1big30/trees/t1_$SEED
HERE=$(cd "$(dirname "$0")" && pwd)
RUN=$OUT/${SEED}_$P; CACHE=$OUT/cache${SEED}_$P
T0=$(date +%s); echo "t1 $SEED $P start $(date -u +%T)" >> $OUT/t1.log
(cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
   $HERE/dbench.py $CACHE $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' \
   "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
RC=$?; echo "t1 $SEED $P rc=$RC end $(date -u +%T) wall_s=$(( $(date +%s) - T0 ))" >> $OUT/t1.log
