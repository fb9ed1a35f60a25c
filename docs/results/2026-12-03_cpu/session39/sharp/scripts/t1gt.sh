#!/bin/bash
# t1gt.sh: Table 1 (photo appearance), ground-truth masks (oracle) with the fit, both arms side by side, one thread each.
W=/tmp/w39/outputs/demo
run() { arm=$1; code=$2; tree=$3
  OMP_NUM_THREADS=1 PYTHONPATH=$code/src /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=/tmp/trees/$tree 'data.image_size=[312,96]' \
    run=$W 'compose=[photo]' 'proposals=[gt]' scene=derender threads=1 examples=0 output_dir=/tmp/s39h/t1/${tree}_$arm \
    > /tmp/s39h/t1_${tree}_$arm.log 2>&1; echo "$arm $tree rc=$? $(date +%T)"; }
mkdir -p /tmp/s39h/t1
run main /work/wt_base h2429 & run sharp /work/wt_new h2429 & wait
run main /work/wt_base g2433 & run sharp /work/wt_new g2433 & wait
