#!/bin/bash
# ev2.sh NAME ENV [KEY=VALUE ...]: as ev.sh with an environment assignment (exploration switches).
cd /work/wt/s6-cost
NAME=$1; E=$2; shift 2
env $E STRIDE=2 PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s6data/cost/evalfit.py /tmp/s4data/cost/val13_capture.pt /tmp/s6data/cost/val13/$NAME.json "$@" > /tmp/s6data/cost/val13/$NAME.log 2>&1
