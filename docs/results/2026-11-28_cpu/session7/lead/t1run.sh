#!/bin/bash
# t1run.sh TAG TREE PROPOSALS SCENE [overrides]: Table 1 photo row with the session-5 demo weights, lead worktree
tag=$1; tree=$2; p=$3; sc=$4; shift 4; out=/tmp/s7data/lead/t1_$tag
cd /work/wt/s7-lead && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 nice -n 3 /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=$tree 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[$p]" scene=$sc threads=1 examples=0 output_dir=$out "$@" > $out.log 2>&1
echo "done $tag rc=$?"
