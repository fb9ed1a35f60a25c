#!/bin/bash
# heldout.sh: held-out seed 2113, generated after the code was final and measured once: the two trees made as session
# 10's 2103 (session 5's gen_cf.py, worlds 0001,0002, 6 cars; session 9's gen_rot.py, rotated cameras), then session
# 10's bench.sh (sdn3d-bench counterfactual=true counterfactual_kinds=[delete], oracle source: ground-truth geometry)
# with every fill, the learnt one with the packaged weights (photo.learnt_weights=null), and session 10's paired.py.
D=/tmp/s11data/fill2/held; WT=$(cd "$(dirname "$0")/../../../../.." && pwd); H=$(dirname "$0")
R=$WT/docs/results; S10=$R/2026-11-29_cpu/session10/learntfill
PY="nice -n 5 env PYTHONPATH=$WT/src:$WT OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
mkdir -p $D
$PY $R/2026-11-28_cpu/session5/turns/gen_cf.py $D/cf2113 2113 0001,0002 6 > $D/cf2113.gen.log 2>&1
$PY $R/2026-11-29_cpu/session9/lead/gen_rot.py $D/rot2113 2113 > $D/rot2113.gen.log 2>&1
for T in cf2113 rot2113; do nice -n 5 $S10/bench.sh $D/$T $D/${T}_held [auto,telea,patchmatch,rays,learnt]; done
$PY $S10/paired.py $D/cf2113_held/counterfactual.json $D/rot2113_held/counterfactual.json > $H/heldout2113.md
