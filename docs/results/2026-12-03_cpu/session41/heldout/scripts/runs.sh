#!/bin/bash
# runs.sh TREE OUT: the plan's Table 1 runs on TREE (two at a time), outputs in OUT/<run>.
# E21=none: the two main runs alone (the replication on 2441).
set -u
TREE=$1; OUT=$2; PY=/work/main/.venv/bin/python
E21=${E21:-/tmp/s41/sem/e21/checkpoints/best-epoch020.ckpt}
run() { name=$1; prop=$2; shift 2
  (OMP_WAIT_POLICY=PASSIVE $PY -m sdn3d.cli.bench data.root=$TREE 'data.image_size=[312,96]' run=/tmp/w39/outputs/demo \
    'compose=[photo]' "proposals=[$prop]" scene=derender threads=1 examples=8 output_dir=$OUT/$name "$@") > $OUT/$name.log 2>&1
  echo "$name rc=$?"; }
mkdir -p "$OUT"
run pred_main semantic & run gt_main gt & wait
[ "$E21" = none ] || run pred_e21 semantic checkpoints.semantic=$E21
