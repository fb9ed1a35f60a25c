#!/bin/bash
# data.sh: the training (tr*) and validation (va*) trees of session 11's learnt fill, generated and extracted in turn
# (seeds 300-399 only). Validation trees follow the held-out recipes (gen_cf.py: worlds 0001,0002, clone+fog, 6 cars,
# 30 frames; gen_rot.py: worlds 0001,0002, three rotated cameras, 8 cars, 30 frames), without turn pairs.
D=/tmp/s11data/fill2; WT=$(cd "$(dirname "$0")/../../../../.." && pwd); H=$(dirname "$0")
PY="nice -n 5 env PYTHONPATH=$WT/src:$WT OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
one() { # NAME SEED WORLDS VARIATIONS CARS FRAMES
  [ -f $D/$1.npz ] && return
  $PY $H/gen_pairs.py $D/$1 $2 $3 $4 $5 $6 > $D/$1.gen.log 2>&1
  $PY $WT/benchmarks/learnt_fill.py extract $D/$1 $D/$1.npz > $D/$1.ext.log 2>&1
  echo "$1 $(date -u +%H:%M:%S) $(tail -1 $D/$1.ext.log)"
}
A=0001,0002; B=0006,0018,0020
one va390cf 390 $A clone,fog 6 30
one tr310 310 $A clone,fog,rain,overcast 6 10
one va391rot 391 $A 30-deg-right,15-deg-left,30-deg-left 8 30
one tr311 311 $A 30-deg-right,15-deg-left,30-deg-left,15-deg-right 6 10
one tr312 312 $B clone,fog,morning,sunset 6 10
one tr313 313 $A clone,fog,morning,sunset 6 10
one tr314 314 $A 30-deg-right,15-deg-left,30-deg-left,15-deg-right 6 10
one tr315 315 $B rain,overcast,30-deg-right,15-deg-left 6 10
one tr316 316 $A clone,fog,rain,overcast 6 10
one tr317 317 $A 30-deg-right,15-deg-left,30-deg-left,15-deg-right 6 10
