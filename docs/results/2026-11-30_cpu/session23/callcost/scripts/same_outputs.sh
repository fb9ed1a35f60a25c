#!/bin/bash
# same_outputs.sh OUT NAME=TREE... : the exact cuts' identity check. Each code tree (a git archive of src and conf)
# runs the same sdn3d-edit calls into OUT/<NAME>/<call>: issue 40's benchmark call (session 12's spec31: 10 boxes
# and a rotate, t1_31's frame 0001/clone/00000 at 624x192, threads=2) and its listing (list=true), and the real frame of tests/data through its two
# boxes (README's "Edit your own image"): listed, car 12001 turned 90 degrees, car 12002 deleted, car 12001
# recoloured blue (threads=1). Then compare_outputs.py compares every file of the first tree's calls with the others'.
#   bash same_outputs.sh /tmp/s23data/callcost/same main=/tmp/s23data/lead/base_a9c br=/tmp/s23data/callcost/br
set -e
OUT=$1; shift
WT=$(cd "$(dirname "$0")/../../../../../.." && pwd)
RUNS=/tmp/s21data/demo/out/runs
FRAME=$WT/tests/data/0006_30-deg-right_00043.png
mkdir -p "$OUT/specs"
BOXES='[{box: [466, 203, 666, 333], class: Car}, {box: [704, 194, 917, 305], class: Car}]'
echo "{objects: $BOXES, ops: []}" > "$OUT/specs/listed.yaml"
echo "{objects: $BOXES, ops: [{op: rotate, id: 12001, ry_deg: 90}]}" > "$OUT/specs/turn90.yaml"
echo "{objects: $BOXES, ops: [{op: delete, id: 12002}]}" > "$OUT/specs/delete.yaml"
echo "{objects: $BOXES, ops: [{op: recolor, id: 12001, color: blue}]}" > "$OUT/specs/blue.yaml"
for PAIR in "$@"; do
  NAME=${PAIR%%=*}; TREE=${PAIR#*=}
  run() {  # run CALL THREADS ARGS...
    local call=$1 threads=$2; shift 2
    env -u PYTHONDONTWRITEBYTECODE PYTHONPATH="$TREE/src" SDN3D_CONFIG_DIR="$TREE/conf" OMP_NUM_THREADS=$threads \
      nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.edit run=$RUNS "$@" threads=$threads \
      output_dir="$OUT/$NAME/$call" overwrite=true > "$OUT/$NAME/$call.log" 2>&1
  }
  mkdir -p "$OUT/$NAME"
  run bench 2 input.image=/tmp/s23data/lead/in624.png \
    edits="$WT/docs/results/2026-11-28_cpu/session4/cost/spec31.yaml"
  run bench_list 2 input.image=/tmp/s23data/lead/in624.png \
    edits="$WT/docs/results/2026-11-28_cpu/session4/cost/spec31.yaml" list=true
  for S in listed turn90 delete blue; do
    run real_$S 1 input.image="$FRAME" proposals=boxes edits="$OUT/specs/$S.yaml"
  done
  echo "$NAME done $(date -u +%T)"
done
/work/main/.venv/bin/python "$(dirname "$0")/compare_outputs.py" "$OUT" "${@%%=*}"
