#!/bin/bash
# t1.sh CODE_DIR NAME SEED...: Table 1 photo row at 312x96, ground-truth masks (oracle), on session 11's tuning trees
# t1_SEED (session 11 semrain's dbench.py), de-renders read from copies of session 16's caches in
# /tmp/s17data/glass/t1/cacheSEED (this branch does not change the de-render); outputs /tmp/s17data/glass/t1/.
set -u
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s17data/glass/t1
R=$(cd "$(dirname "$0")/../../.." && pwd)
DBENCH=$R/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  RUN=$OUT/t1_${SEED}_gt_$NAME
  (cd "$CODE" && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH \
    $OUT/cache$SEED $RUN.dump data.root=/tmp/s11data/semrain/t1_$SEED 'data.image_size=[312,96]' \
    run=/tmp/s11data/demo/out 'compose=[photo]' 'proposals=[gt]' scene=derender threads=1 examples=0 \
    output_dir=$RUN > $RUN.log 2>&1)
  echo "t1 $SEED $NAME rc=$? $(date -u +%T)" >> $OUT/t1.log
done
