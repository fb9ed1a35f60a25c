#!/bin/bash
# turns.sh OUT SOURCES [overrides...]: counterfactual turns of tuning tree cf31 (main's work tree), photo:auto
out=$1; src=$2; shift 2
cd /work/main && PYTHONPATH=/work/main/src:/work/main OMP_NUM_THREADS=1 nice -n 5 .venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s11data/lead/cf31 output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' "counterfactual_sources=$src" run=/tmp/s11data/demo/out/runs examples=0 threads=1 "$@" > $out.log 2>&1
echo "done $out rc=$?"
