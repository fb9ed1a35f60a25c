#!/bin/bash
# data3.sh: more training trees after data.sh, in session 10's gen_train.py's variety (all five worlds, 6 cars,
# 10 frames), seed 325 (326-329 were cut for time), as data.sh's one().
D=/tmp/s11data/fill2; WT=$(cd "$(dirname "$0")/../../../../.." && pwd); H=$(dirname "$0")
PY="nice -n 5 env PYTHONPATH=$WT/src:$WT OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
one() { # NAME SEED WORLDS VARIATIONS CARS FRAMES
  [ -f $D/$1.npz ] && return
  $PY $H/gen_pairs.py $D/$1 $2 $3 $4 $5 $6 > $D/$1.gen.log 2>&1
  $PY $WT/benchmarks/learnt_fill.py extract $D/$1 $D/$1.npz > $D/$1.ext.log 2>&1
  echo "$1 $(date -u +%H:%M:%S) $(tail -1 $D/$1.ext.log)"
}
W=0001,0002,0006,0018,0020
one tr325 325 $W clone,fog,30-deg-right,15-deg-left 6 10
