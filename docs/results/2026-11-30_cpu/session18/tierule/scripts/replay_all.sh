#!/bin/bash
# replay_all.sh REGS SEED...: replay.py on the captures of capture_all.sh (semantic proposals, then ground-truth masks
# (oracle)), one JSON per tree and row (name suffix: $TAG) in /tmp/s18data/tierule/replay/.
HERE=$(cd $(dirname $0) && pwd); CODE=/work/wt/tierule; REGS=$1; shift; OUT=/tmp/s18data/tierule/replay; mkdir -p $OUT
for SEED in "$@"; do
  case $SEED in 31) TREE=/tmp/s11data/lead/t1_31;; 35|37) TREE=/tmp/s11data/semrain/t1_$SEED;;
    *) TREE=/tmp/s18data/tierule/t1_$SEED;; esac
  for P in semantic gt; do
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $HERE/replay.py \
       $TREE /tmp/s18data/tierule/cap/${P}$SEED $OUT/${P}$SEED${TAG:-}.json $REGS > $OUT/${P}$SEED${TAG:-}.log 2>&1)
    echo "replay $SEED $P rc=$? $(date -u +%T)" >> $OUT/done.log
  done
done
