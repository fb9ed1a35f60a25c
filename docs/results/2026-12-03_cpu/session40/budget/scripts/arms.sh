#!/bin/bash
# arms.sh TREE OUT: the plan's four Table 1 runs on TREE (two at a time), outputs in OUT/<arm>.
set -u
TREE=$1; OUT=$2; HERE=$(cd "$(dirname "$0")" && pwd); PY=/work/main/.venv/bin/python
run() { (FITOV=$1 $PY "$HERE/swap_bench.py" data.root=$TREE 'data.image_size=[312,96]' run=/tmp/w39/outputs/demo \
  'compose=[photo]' "proposals=[$3]" scene=derender threads=1 examples=0 output_dir=$OUT/$2) > $OUT/$2.log 2>&1; }
mkdir -p "$OUT"
run "" gt_main gt & run "fine_steps=48,fine_size=96" gt_big gt & wait
run "" pred_main semantic & run "fine_steps=48,fine_size=96" pred_big semantic & wait
