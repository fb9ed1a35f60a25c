#!/bin/bash
# misses.sh CODE SEED...: misses.py on the delete and occluder-removed entries of the Table 1 trees SEED, both rows
# (semantic proposals; ground-truth masks (oracle)), the de-render caches of t1.sh (/tmp/s26data/del41/t1/cache<SEED>),
# w0, 312x96, one thread. Writes $OUT (default /tmp/s26data/del41/miss)/<SEED>_<row>.json and .log; ROWS: the rows.
CODE=$1; shift; OUT=${OUT:-/tmp/s26data/del41/miss}; mkdir -p $OUT; HERE=$(cd "$(dirname "$0")" && pwd)
for SEED in "$@"; do
  TREE=/tmp/s21data/trees/t1_$SEED; [ -d $TREE ] || TREE=/tmp/s25data/del40/trees/t1_$SEED
  ONLY=$(PYTHONPATH=$CODE/src /work/main/.venv/bin/python $HERE/kinds.py $TREE)
  for P in ${ROWS:-semantic gt}; do
    (cd $CODE && ONLY=$ONLY PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
       $HERE/misses.py /tmp/s26data/del41/t1/cache$SEED $OUT/${SEED}_$P.json data.root=$TREE 'data.image_size=[312,96]' \
       run=/tmp/s21data/demo/out 'compose=[photo]' "proposals=[$P]" scene=derender threads=1 examples=0 \
       output_dir=$OUT/run${SEED}_$P > $OUT/${SEED}_$P.log 2>&1)
    echo "miss $SEED $P rc=$? $(date -u +%T)" >> $OUT/miss.log
  done
done
