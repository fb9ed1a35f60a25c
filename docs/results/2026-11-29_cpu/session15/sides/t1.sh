#!/bin/bash
# t1.sh CODE_DIR NAME SEED...: Table 1 photo row, ground-truth masks (oracle), 312x96, session 11 semrain's dbench.py
S=$1; N=$2; shift 2; O=/tmp/s15data/sides/t1; mkdir -p $O
DB=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SEED in "$@"; do TREE=/tmp/s11data/semrain/t1_$SEED
  (cd $S && PYTHONPATH=$S/src:$S OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DB /tmp/s15data/sides/cache$SEED $O/t1_${SEED}_gt_$N.dump data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[gt]" scene=derender threads=1 examples=0 output_dir=$O/t1_${SEED}_gt_$N > $O/t1_${SEED}_gt_$N.log 2>&1)
  echo "t1 $SEED $N rc=$? $(date -u +%T)" >> $O/t1.log
done
