#!/bin/bash
# replay_all.sh CODE TAG FIELDS SEED...: replay.py (code tree CODE, FitSettings fields FIELDS, "" for the defaults) on
# capture_all.sh's captures (semantic proposals, then ground-truth masks (oracle)); one JSON per tree and row,
# /tmp/s20data/flip/replay/<row><SEED>_<TAG>.json.
HERE=$(cd $(dirname $0) && pwd); CODE=$1; TAG=$2; FIELDS=$3; shift 3; OUT=/tmp/s20data/flip/replay; mkdir -p $OUT
for SEED in "$@"; do
  case $SEED in 31) TREE=/tmp/s11data/lead/t1_31;; 35|37) TREE=/tmp/s11data/semrain/t1_$SEED;;
    *) TREE=/tmp/s20data/flip/t1_$SEED;; esac
  for P in ${ROWS:-semantic gt}; do
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $HERE/replay.py \
       $TREE /tmp/s20data/flip/cap/${CAP:-}$P$SEED $OUT/$P${SEED}_$TAG.json $FIELDS > $OUT/$P${SEED}_$TAG.log 2>&1)
    echo "replay $TAG $SEED $P rc=$? $(date -u +%T)" >> $OUT/done.log
  done
done
