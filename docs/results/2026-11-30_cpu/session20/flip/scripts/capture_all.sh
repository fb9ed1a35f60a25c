#!/bin/bash
# capture_all.sh CODE TAG SEED...: capture.py (code tree CODE) on the tuning trees' semantic and ground-truth-mask
# (oracle) source scenes named by session 17 lead's de-render caches (cache_rows*; the same trees, so the same
# Table 1 sources); captures in /tmp/s20data/flip/cap/<TAG><row><SEED>/.
HERE=$(cd $(dirname $0) && pwd); CODE=$1; TAG=$2; shift 2; OUT=/tmp/s20data/flip/cap; mkdir -p $OUT
for SEED in "$@"; do
  case $SEED in 31) TREE=/tmp/s11data/lead/t1_31; SRC=/tmp/s17data/lead/t1/cache_rows31;;
    35|37) TREE=/tmp/s11data/semrain/t1_$SEED; SRC=/tmp/s17data/lead/t1/cache_rows$SEED;;
    *) TREE=/tmp/s20data/flip/t1_$SEED; SRC=${SRC_CACHE:?};; esac
  for P in semantic gt; do
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $HERE/capture.py \
       $TREE $SRC $OUT/$TAG$P$SEED $P > $OUT/$TAG$P$SEED.log 2>&1)
    echo "capture $TAG $SEED $P rc=$? $(date -u +%T)" >> $OUT/done.log
  done
done
