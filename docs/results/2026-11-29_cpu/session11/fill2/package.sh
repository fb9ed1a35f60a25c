#!/bin/bash
# package.sh: rebuilds the packaged weights src/sdn3d/resources/learnt_fill.pt of session 11 (one thread; each step
# deterministic given its seed). Members:
#  1. session 10's net (its README: gen_train.py seeds 300-305 with the default variations and 307, 308 with
#     rain,morning,sunset,overcast,30-deg-left,15-deg-right; benchmarks/learnt_fill.py extract each; train on the
#     eight files --steps 1200 --width 16 --seed 0), saved as $D/w_s10.pt;
#  2.-4. data.sh and data3.sh's training trees (seeds 310-317, 325), train.sh b32s0 32 0, b32s1 32 1, b32s2 32 2.
# The validation trees (va390cf, va391rot) are scored by train.sh; compare.py makes the table.
D=/tmp/s11data/fill2; WT=$(cd "$(dirname "$0")/../../../../.." && pwd)
cd $WT && PYTHONPATH=$WT/src:$WT OMP_NUM_THREADS=1 /work/main/.venv/bin/python benchmarks/learnt_fill.py ensemble \
  src/sdn3d/resources/learnt_fill.pt $D/w_s10.pt $D/w_b32s0.pt $D/w_b32s1.pt $D/w_b32s2.pt
