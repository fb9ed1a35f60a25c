#!/bin/bash
# tt3.sh TAG TREE VARIANT [overrides]
tag=$1; tree=$2; var=$3; shift 3; out=/tmp/s7data/lead/tt_$tag
cd /work/wt/s7-lead && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/lead/runvar.py $var counterfactual=true data.root=$tree output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' examples=0 "$@" > $out.log 2>&1
echo "done $tag rc=$?"
