#!/bin/bash
# tt_main.sh CODE TAG TREE [overrides]: turns bench (oracle geometry)
code=$1; tag=$2; tree=$3; shift 3; out=/tmp/s7data/lead/tt_$tag
cd $code && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$tree output_dir=$out examples=0 "$@" > $out.log 2>&1
echo "done $tag rc=$?"
