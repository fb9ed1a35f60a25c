#!/bin/bash
# cf.sh CODE_DIR OUT [TREE]: counterfactual turns+deletes on cf31 (oracle geometry), code CODE_DIR (src+conf)
code=$1; out=$2; T=${3:-/tmp/s5data/turns/cf31}
cd $code && PYTHONPATH=$code/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$T output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn,delete]' examples=0 > $out.log 2>&1
echo "done $out rc=$?"
