#!/bin/bash
# tt2.sh TAG TREE [overrides] : turns bench (oracle geometry) in the lead worktree
tag=$1; tree=$2; shift 2; out=/tmp/s7data/lead/tt_$tag
cd /work/wt/s7-lead && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$tree output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' examples=0 "$@" > $out.log 2>&1
echo "done $tag rc=$?"
