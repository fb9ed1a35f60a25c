#!/bin/bash
# t1.sh TAG TREE [env...]: Table 1's predicted row (photo appearance, 312x96) with the lane experiment's code
tag=$1; tree=$2; shift 2
W=${W:-/tmp/w38}
cd /work/wt_lane
env "$@" PYTHONPATH=/work/wt_lane/src /work/main/.venv/bin/python /work/notes/s38/lane/run.py -m sdn3d.cli.bench data.root=$tree 'data.image_size=[312,96]' run=$W/outputs/demo 'compose=[photo]' "proposals=[semantic]" scene=derender threads=1 examples=0 output_dir=/tmp/lane/t1_$tag > /tmp/lane/t1_$tag.log 2>&1
