#!/bin/bash
# t1o.sh TAG TREE ORACLE [env...]: t1.sh with session 37's oracle_pose.py swapping ORACLE fields of the truth in
tag=$1; tree=$2; oracle=$3; shift 3
W=${W:-/tmp/w38}
cd /work/wt_lane
env "$@" ORACLE=$oracle PYTHONPATH=/work/wt_lane/src /work/main/.venv/bin/python /work/notes/s38/lane/run.py /work/main/docs/results/2026-12-02_cpu/session37/lead/posediag/scripts/oracle_pose.py data.root=$tree 'data.image_size=[312,96]' run=$W/outputs/demo 'compose=[photo]' "proposals=[semantic]" scene=derender threads=1 examples=0 output_dir=/tmp/lane/t1_$tag > /tmp/lane/t1_$tag.log 2>&1
