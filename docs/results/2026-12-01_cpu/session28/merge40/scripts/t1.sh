#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (semantic proposals, then ground-truth masks (oracle)) of the
# code tree CODE, session 21's demo weights (w0), by session 11 semrain's dbench.py: session 21 lead's rows/t1.sh
# with session 27 join40 paths (a copy of session 26 frag40 t1.sh). Outputs /tmp/s27data/join40/t1/<NAME><SEED>_<row>{,.dump,.log}; de-render caches
# /tmp/s27data/join40/t1/cache<SEED><CACHE_TAG>. Trees: /tmp/s21data/trees/t1_<SEED> when it exists, else
# /tmp/s25data/del40/trees/t1_<SEED>, else /tmp/s27data/join40/trees/t1_<SEED>. KINDS: evaluate only the entries of these edit kinds (default "delete
# occluder_removed"; "all": every entry), by kinds.py and dbench.py's ONLY=.
# EXTRA: further sdn3d-bench overrides (e.g. +photo.fit_band_px=8: conf/bench.yaml names only some photo keys).
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s27data/join40/t1; mkdir -p $OUT; WEIGHTS=${WEIGHTS:-/tmp/s21data/demo/out}
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
HERE=$(cd "$(dirname "$0")" && pwd)
for SEED in "$@"; do
  TREE=/tmp/s21data/trees/t1_$SEED; [ -d $TREE ] || TREE=/tmp/s25data/del40/trees/t1_$SEED; [ -d $TREE ] || TREE=/tmp/s27data/join40/trees/t1_$SEED
  CACHE=$OUT/cache$SEED${CACHE_TAG:-}
  ONLY=""
  if [ "${KINDS:-}" != all ]; then
    ONLY=$(PYTHONPATH=$CODE/src /work/main/.venv/bin/python $HERE/kinds.py $TREE ${KINDS:-delete occluder_removed})
  fi
  for P in ${ROWS:-semantic gt}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && ONLY=$ONLY PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
       $DBENCH $CACHE $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' \
       "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN ${EXTRA:-} > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
