#!/bin/bash
# cfset.sh NAME ARGS... : counterfactual turns on cf33 (tuning), oracle geometry and GT masks
name=$1; shift
PYTHONPATH=/work/main/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s3data/cf33 run=/work/final_demo 'counterfactual_kinds=[turn]' 'counterfactual_fills=[rays]' 'counterfactual_sources=[oracle,gt]' threads=1 output_dir=/tmp/s4data/lead/runs/$name "$@" > /tmp/s4data/lead/$name.log 2>&1
