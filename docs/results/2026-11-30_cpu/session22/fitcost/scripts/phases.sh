#!/bin/bash
# phases.sh OUTDIR ROUNDS NAME=TREE...: benchmarks/edit_cost.py (each tree's own copy, which imports that tree's src)
# on issue 40's benchmark call at threads=1, the trees taking turns, ROUNDS rounds: OUTDIR/phases_<NAME>_r<k>.json.
OUT=$1; ROUNDS=$2; shift 2
WT=$(cd "$(dirname "$0")/../../../../../.." && pwd)
for K in $(seq 1 $ROUNDS); do
  for PAIR in "$@"; do
    NAME=${PAIR%%=*}; TREE=${PAIR#*=}
    env -u PYTHONDONTWRITEBYTECODE SDN3D_CONFIG_DIR=$TREE/conf OMP_NUM_THREADS=1 nice -n 5 \
      /work/main/.venv/bin/python $TREE/benchmarks/edit_cost.py --out $OUT/phases_${NAME}_r$K.json -- \
      run=/tmp/s21data/demo/out/runs input.image=/tmp/s22data/fitcost/in624.png \
      edits=$WT/docs/results/2026-11-28_cpu/session4/cost/spec31.yaml output_dir=/tmp/s22data/fitcost/ph_$NAME \
      overwrite=true threads=1 > /dev/null 2>&1
  done
done
