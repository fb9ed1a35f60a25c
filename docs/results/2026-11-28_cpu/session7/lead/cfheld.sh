#!/bin/bash
# cfheld.sh CODE TAG [overrides]: counterfactual turns on held-out cf2087
code=$1; tag=$2; shift 2; out=/tmp/s7data/lead/cf2087_$tag
cd $code && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s7data/lead/cf2087 output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' "$@" > $out.log 2>&1
echo "done $tag rc=$?"
