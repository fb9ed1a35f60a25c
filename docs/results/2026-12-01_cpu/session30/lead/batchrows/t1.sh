#!/bin/bash
# t1.sh CODE NAME SEED: Table 1 predicted row (semantic proposals), photo, 312x96, w30, every entry.
CODE=$1; NAME=$2; SEED=$3; OUT=/tmp/s30/lead/t1; mkdir -p $OUT
RUN=$OUT/${NAME}${SEED}
(cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
  data.root=/tmp/s30/lead/trees/t1_$SEED 'data.image_size=[312,96]' run=/tmp/s30/demo/outputs/demo 'compose=[photo]' \
  "proposals=[semantic]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
echo "t1 $NAME $SEED rc=$? $(date -u +%T)" >> $OUT/t1.log
