#!/bin/bash
# held-out seed 2069 counterfactual deletes: main (774bffb) or final (4bf8110), oracle scene, every fill
who=$1; DIR=/tmp/s5data/deletes/$who
cd $DIR && PYTHONPATH=$DIR/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s5data/deletes/cf2069 \
  output_dir=/tmp/s5data/deletes/bench_cf2069_$who 'counterfactual_fills=[auto,telea,patchmatch,rays]' 'counterfactual_kinds=[delete]' \
  'counterfactual_sources=[oracle]' checkpoints.textural=/work/final_demo/runs/textural/checkpoints/inference.pt > /tmp/s5data/deletes/bench_cf2069_$who.log 2>&1
echo done $who
