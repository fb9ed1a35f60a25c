#!/bin/bash
# inside.sh OUT ROUNDS: per round, for main's plain tree then this branch's archive, one gc_time.py call and one
# deep_stages.py call (the spec31 edit, threads=2, w0 run=); gc lines to OUT/gc.jsonl, stages to
# OUT/stages_<tree>_<i>.json. BRANCH: the branch tree (default /tmp/s26data/cost40/tree_cost40).
OUT=$1; ROUNDS=${2:-3}; mkdir -p $OUT; S=/work/wt/cost40/docs/results/2026-11-30_cpu/session26/cost40/scripts
SPEC=/work/wt/cost40/docs/results/2026-11-28_cpu/session4/cost/spec31.yaml
for i in $(seq 1 $ROUNDS); do
  for T in main=/tmp/s26data/lead/base_9fa cost40=${BRANCH:-/tmp/s26data/cost40/tree_cost40}; do
    NAME=${T%%=*}; CODE=${T#*=}
    cd $CODE && export OMP_NUM_THREADS=1 PYTHONPATH=$CODE/src SDN3D_CONFIG_DIR=$CODE/conf
    nice -n 5 /work/main/.venv/bin/python $S/gc_time.py $NAME /tmp/s26data/cost40/in31.png $SPEC /tmp/s21data/demo/out 2 \
      2>/dev/null >> $OUT/gc.jsonl
    nice -n 5 /work/main/.venv/bin/python $S/deep_stages.py /tmp/s26data/cost40/in31.png $SPEC /tmp/s21data/demo/out 2 \
      $OUT/stages_${NAME}_$i.json > /dev/null 2>&1
  done
  uptime >> $OUT/load.txt
done
