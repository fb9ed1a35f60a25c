#!/bin/bash
# train.sh NAME SIDE SEED [STEPS]: benchmarks/learnt_fill.py train on every training tree (tr3*.npz) at working side
# SIDE with seed SEED (1200 steps unless STEPS, width 16, batch 32, lr 2e-3), then its validation score (va3*.npz).
D=/tmp/s11data/fill2; WT=$(cd "$(dirname "$0")/../../../../.." && pwd)
PY="nice -n 5 env PYTHONPATH=$WT/src:$WT OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
$PY $WT/benchmarks/learnt_fill.py train $D/w_$1.pt $D/tr3*.npz --side $2 --seed $3 --steps ${4:-1200} > $D/w_$1.train.log 2>&1
$PY $WT/benchmarks/learnt_fill.py score $D/w_$1.pt $D/va3*.npz --json $D/score_$1.json > $D/score_$1.txt 2>&1
echo "$1 $(date -u +%H:%M:%S)"; cat $D/score_$1.txt
