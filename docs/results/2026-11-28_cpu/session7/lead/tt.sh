#!/bin/bash
# tt.sh TAG TREE RPARTS RPOW : turns bench (oracle geometry) in the lead worktree
tag=$1; tree=$2; out=/tmp/s7data/lead/tt_$tag
cd /work/wt/s7-lead && SDN3D_RPARTS="$3" SDN3D_RPOW="$4" PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$tree output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' examples=0 > $out.log 2>&1
echo "done $tag rc=$?"
