#!/bin/bash
# tune.sh NAME:SRC[,NAME:SRC...] OUT STEP...: tuning runs, one at a time under nice: each STEP is cfTREE:SOURCE
# (sdn3d-bench counterfactual=true on /tmp/s11data/lead/cf31 or /tmp/s14data/ends/cf33, turns only, photo fill rays;
# SOURCE oracle = ground-truth geometry, semantic = predicted with the session 11 demo's branches) or t1SEED:gt
# (Table 1 photo row on /tmp/s11data/semrain/t1_SEED, ground-truth masks (oracle), session 11 semrain's dbench.py as
# session 13 rotloss's run.sh drives it, the de-renders cached: they do not depend on the part labels), each for
# code in turn (SRC: a git archive, "SRC/src"; NAME: the outputs' suffix).
set -u
CODES=${1//,/ }; O=$2; shift 2; mkdir -p $O
CK="checkpoints.semantic=/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s11data/demo/out/runs/geometric/checkpoints/inference.pt"
DB=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for STEP in "$@"; do
  for C in $CODES; do
    S=${C#*:}; N=${C%%:*}
    case $STEP in
      cf31:*|cf33:*) T=${STEP%%:*}; SRC=${STEP#*:}; [ $T = cf31 ] && TREE=/tmp/s11data/lead/cf31 || TREE=/tmp/s14data/ends/cf33
        EXTRA=""; [ $SRC = semantic ] && EXTRA=$CK
        (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$TREE output_dir=$O/${T}_${SRC}_$N examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_kinds=[turn]' "counterfactual_sources=[$SRC]" $EXTRA > $O/${T}_${SRC}_$N.log 2>&1) ;;
      t1*:gt) SEED=${STEP%%:*}; SEED=${SEED#t1}; [ $SEED = 31 ] && TREE=/tmp/s11data/lead/t1_31 || TREE=/tmp/s11data/semrain/t1_$SEED
        (cd $S && PYTHONPATH=$S/src:$S OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DB /tmp/s14data/ends/cache$SEED $O/t1_${SEED}_gt_$N.dump data.root=$TREE 'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[gt]" scene=derender threads=1 examples=0 output_dir=$O/t1_${SEED}_gt_$N > $O/t1_${SEED}_gt_$N.log 2>&1) ;;
    esac
    echo "$STEP $N rc=$? $(date -u +%T)" >> $O/tune.log
  done
done
