#!/bin/bash
# truepose.sh CODE NAME: the occluder-removed entries of the three Table 1 tuning trees with ground-truth geometry and
# masks (scene=oracle: SceneCode.from_frame, an oracle), photo appearance at 312x96, weights w0 (the textural branch
# is not used by the photo appearance), by session 11 semrain's dbench.py (ONLY= the occluder entries). Issue 40 item
# 4's check: does amodal completion still cost occluder removals with true poses? Outputs
# /tmp/s22data/occl/tp/<NAME><SEED>{,.dump,.log}.
CODE=$1; NAME=$2; OUT=/tmp/s22data/occl/tp; mkdir -p $OUT
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in 31 35 37; do
  if [ $SEED = 31 ]; then ONLY=25,26,27,28,29,55,56,57,58,59; else
    ONLY=25,26,27,28,29,55,56,57,58,59,85,86,87,88,89,115,116,117,118,119; fi
  RUN=$OUT/${NAME}${SEED}
  (cd $CODE && ONLY=$ONLY PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH \
     $OUT/cache$SEED $RUN.dump data.root=/tmp/s21data/trees/t1_$SEED 'data.image_size=[312,96]' \
     run=/tmp/s21data/demo/out 'compose=[photo]' scene=oracle threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
  echo "tp $NAME $SEED rc=$? $(date -u +%T)" >> $OUT/tp.log
done
