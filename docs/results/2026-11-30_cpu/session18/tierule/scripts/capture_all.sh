#!/bin/bash
# capture_all.sh SEED...: capture.py on the tuning trees' semantic and ground-truth-mask (oracle) source scenes, the
# sources named by session 17 lead's de-render caches of main's fit (cache_rows*); captures in /tmp/s18data/tierule/cap/.
HERE=$(cd $(dirname $0) && pwd); CODE=/work/wt/tierule
for SEED in "$@"; do
  [ $SEED = 31 ] && TREE=/tmp/s11data/lead/t1_31 || TREE=/tmp/s11data/semrain/t1_$SEED
  for P in semantic gt; do
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $HERE/capture.py \
       $TREE /tmp/s17data/lead/t1/cache_rows$SEED /tmp/s18data/tierule/cap/${P}$SEED $P > /tmp/s18data/tierule/cap/${P}$SEED.log 2>&1)
    echo "capture $SEED $P rc=$? $(date -u +%T)" >> /tmp/s18data/tierule/cap/done.log
  done
done
