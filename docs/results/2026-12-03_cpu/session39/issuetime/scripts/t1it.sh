#!/bin/bash
# t1it.sh: Table 1 photo appearance on g2433, issue-time 6c4cf46 against today's code (b3e96112): ground-truth masks
# (scene=derender proposals=[gt]) and ground-truth geometry (scene=oracle); one thread each, two at a time.
W=/tmp/w39/outputs/demo
run() { arm=$1; code=$2; scene=$3; shift 3
  OMP_NUM_THREADS=1 PYTHONPATH=$code/src:$code /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=/tmp/trees/g2433 'data.image_size=[312,96]' \
    run=$W 'compose=[photo]' scene=$scene threads=1 examples=0 output_dir=/tmp/s39h/t1it/g2433_${arm}_$scene "$@" \
    > /tmp/s39h/t1it_${arm}_$scene.log 2>&1; echo "$arm $scene rc=$? $(date +%T)"; }
mkdir -p /tmp/s39h/t1it
run issue /tmp/s39cf/issue_time derender 'proposals=[gt]' & run issue /tmp/s39cf/issue_time oracle & wait
run main /work/wt_new oracle & wait
# and the parent of the first issue-40 commit (git archive 8eaccd1b > /tmp/s39it/code8e), ground-truth geometry:
#   PYTHONPATH=/tmp/s39it/code8e/src:/tmp/s39it/code8e python -m sdn3d.cli.bench data.root=/tmp/trees/g2433 \
#     'data.image_size=[312,96]' run=$W 'compose=[photo]' scene=oracle threads=1 examples=0 output_dir=.../g2433_8e_oracle
