#!/bin/bash
# dc.sh CODE TAG SEED...: dcache.py (main's bench settings, w28, 312x96, predicted proposals) into /tmp/s28/merge40/c/cache<SEED><TAG>
CODE=$1; TAG=$2; shift 2
for SEED in "$@"; do
  (cd $CODE && PYTHONPATH=$CODE/src:$CODE:/work/wt/merge40/docs/results/2026-12-01_cpu/session28/merge40/scripts OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python /work/wt/merge40/docs/results/2026-12-01_cpu/session28/merge40/scripts/dcache.py /tmp/s28/merge40/c/cache$SEED$TAG     data.root=/tmp/s28/merge40/trees/t1_$SEED 'data.image_size=[312,96]' run=/tmp/s28/demo2/outputs/demo 'compose=[photo]'     "proposals=[semantic]" scene=derender threads=1 examples=0 output_dir=/tmp/s28/merge40/c/dc$SEED$TAG > /tmp/s28/merge40/c/dc$SEED$TAG.log 2>&1)
  echo "dc $TAG $SEED rc=$? $(date -u +%T)" >> /tmp/s28/merge40/c/dc.log
done
