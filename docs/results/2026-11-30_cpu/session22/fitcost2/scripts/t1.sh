#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 of the code tree CODE (a git archive with src, conf and
# benchmarks), session 21's demo weights (w0), by session 11 semrain's dbench.py (session 22 fitcost's t1.sh with this
# helper's folders). ROWS: the proposals rows (default: semantic, the predicted row). De-render cache
# /tmp/s22data/fitcost2/t1/cache<SEED>_<NAME> (one per code: the fit's settings change the de-render); outputs
# /tmp/s22data/fitcost2/t1/<NAME><SEED>_<row>{,.dump,.log}. Trees: /tmp/s21data/trees/t1_<SEED>, else this helper's
# /tmp/s22data/fitcost2/trees/t1_<SEED> (2209: the held-out tree).
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s22data/fitcost2/t1; mkdir -p $OUT; WEIGHTS=/tmp/s21data/demo/out
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  TREE=/tmp/s21data/trees/t1_$SEED; [ -d "$TREE" ] || TREE=/tmp/s22data/fitcost2/trees/t1_$SEED
  for P in ${ROWS:-semantic}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && env -u PYTHONDONTWRITEBYTECODE PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 \
       /work/main/.venv/bin/python $DBENCH $OUT/cache${SEED}_$NAME $RUN.dump data.root=$TREE \
       'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' "proposals=[$P]" scene=derender threads=1 \
       examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
