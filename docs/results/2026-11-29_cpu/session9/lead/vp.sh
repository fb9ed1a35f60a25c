#!/bin/bash
# vp.sh TREE TAG [env assignments...]: deletes bench (rays only) in the lead worktree with VP dev env, VP log per pair
tree=$1; tag=$2; shift 2; out=/tmp/s9data/lead/vp_$tag; rm -f $out.vplog
cd ${CODE:-/work/wt/s9-lead} && env "$@" SDN3D_VPLOG=$out.vplog PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$tree output_dir=$out 'counterfactual_fills=[rays]' 'counterfactual_kinds=[delete]' examples=0 > $out.log 2>&1
echo "done $tag rc=$?"
