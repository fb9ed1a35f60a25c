#!/bin/bash
# t1.sh CODE NAME SEED...: Table 1 photo rows at 312x96 (semantic proposals, then ground-truth masks (oracle)) of the
# code tree CODE (a git archive or worktree), session 21's demo weights (/tmp/s21data/demo/out, seed 0, w0), by
# session 11 semrain's dbench.py (session 21 lead's rows/t1.sh with this helper's paths). De-render caches
# /tmp/s23data/rmpred/t1/cache<SEED> (copied from session 22 base2d's / occl's caches of the same weights; new seeds:
# made by the first run); outputs /tmp/s23data/rmpred/t1/<NAME><SEED>_<row>{,.dump,.log}. Trees: t1_<SEED> under
# /tmp/s21data/trees, /tmp/s22data/base2d/trees, /tmp/s22data/occl/trees or /tmp/s23data/rmpred/trees.
# ROWS: the rows to run (default "semantic gt"), one after the other.
CODE=$1; NAME=$2; shift 2; OUT=/tmp/s23data/rmpred/t1; mkdir -p $OUT; WEIGHTS=${WEIGHTS:-/tmp/s21data/demo/out}
DBENCH=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do
  for D in /tmp/s21data/trees /tmp/s22data/base2d/trees /tmp/s22data/occl/trees /tmp/s23data/rmpred/trees; do
    [ -d $D/t1_$SEED ] && TREE=$D/t1_$SEED
  done
  CACHE=$OUT/cache$SEED
  for P in ${ROWS:-semantic gt}; do
    RUN=$OUT/${NAME}${SEED}_$P
    (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DBENCH $CACHE \
       $RUN.dump data.root=$TREE 'data.image_size=[312,96]' run=$WEIGHTS 'compose=[photo]' \
       "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$RUN > $RUN.log 2>&1)
    echo "t1 $NAME $SEED $P rc=$? $(date -u +%T)" >> $OUT/t1.log
  done
done
