#!/bin/bash
# t1pred.sh: Table 1 photo appearance, predicted row (the semantic branch's proposals), on g2433: issue-time 6c4cf46
# against today's code (b3e96112); one thread each, side by side.
W=/tmp/w39/outputs/demo
run() { arm=$1; code=$2
  OMP_NUM_THREADS=1 PYTHONPATH=$code/src:$code /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=/tmp/trees/g2433 'data.image_size=[312,96]' \
    run=$W 'compose=[photo]' 'proposals=[semantic]' scene=derender threads=1 examples=0 output_dir=/tmp/s39h/t1it/g2433_${arm}_semantic \
    > /tmp/s39h/t1pred_$arm.log 2>&1; echo "$arm rc=$? $(date +%T)"; }
run issue /tmp/s39cf/issue_time & run main /work/wt_new & wait
