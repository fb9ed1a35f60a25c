#!/bin/bash
# held-out seed 2075 counterfactual deletes: start (5426919, src_base) or final (this branch's HEAD, final_src), oracle scene, every fill
who=$1; case $who in start) DIR=/tmp/s6data/deletes/src_base;; final) DIR=/tmp/s6data/deletes/final_src;; esac
cd $DIR && PYTHONPATH=$DIR/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s6data/deletes/cf2075 \
  output_dir=/tmp/s6data/deletes/bench_cf2075_$who 'counterfactual_fills=[auto,telea,patchmatch,rays]' 'counterfactual_kinds=[delete]' \
  'counterfactual_sources=[oracle]' checkpoints.textural=/work/final_demo/runs/textural/checkpoints/inference.pt > /tmp/s6data/deletes/bench_cf2075_$who.log 2>&1
echo done $who
