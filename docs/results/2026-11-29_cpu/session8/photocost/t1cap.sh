#!/bin/bash
# captures render_photo's inputs of the Table 1 bench on t1_31 (demo weights of session 5), main's code
W=/work/wt/s8-photocost/docs/results/2026-11-29_cpu/session8/photocost
for sc in "gt derender" "semantic derender" "gt oracle"; do set -- $sc
cd /tmp && PYTHONPATH=/tmp/s8data/photocost/src_main:/work/wt/s8-photocost OMP_NUM_THREADS=1 nice -n 3 /work/main/.venv/bin/python $W/capture_bench.py /tmp/s8data/photocost/t1cap/$1_$2 data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[$1]" scene=$2 threads=1 examples=0 output_dir=/tmp/s8data/photocost/t1bench/$1_$2 > /tmp/s8data/photocost/t1cap_$1_$2.log 2>&1
echo "done $1_$2 rc=$?"
done
