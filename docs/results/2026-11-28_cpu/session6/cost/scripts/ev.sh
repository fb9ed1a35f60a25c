#!/bin/bash
# ev.sh NAME [KEY=VALUE ...]: evalfit on val13 (stride 2) with this worktree's code, log + JSON in val13/.
cd /work/wt/s6-cost
NAME=$1; shift
STRIDE=2 PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s6data/cost/evalfit.py /tmp/s4data/cost/val13_capture.pt /tmp/s6data/cost/val13/$NAME.json "$@" > /tmp/s6data/cost/val13/$NAME.log 2>&1
