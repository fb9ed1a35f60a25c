#!/bin/bash
# usage: bench.sh CODE_DIR TREE OUT [extra overrides...]
code=$1; tree=$2; out=$3; shift 3
cd $code && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$tree output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' "$@" > $out.log 2>&1
echo "done $out rc=$?"
