#!/bin/bash
# held.sh: held-out seed 2117, generated after the code was final (the branch's library reverted to main's: the
# GrabCut reach lost on tuning seed 37), with session 9 fogflip's gen_t1.py recipe (the tuning trees'), measured once:
# main's Table 1 photo rows (semantic proposals, ground-truth masks (oracle)), and the rejected GrabCut reach's
# semantic row for the record (its ground-truth-mask row is main's by construction: the reach is only computed for the
# semantic branch's proposals). Session 11's demo weights.
T=/tmp/s12data/cutmask; W=/work/wt/cutmask; S=$W/docs/results/2026-11-29_cpu/session12/cutmask/scripts
while kill -0 13729 2>/dev/null; do sleep 5; done
cd $W && PYTHONPATH=$T/base/src:$T/base OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T/t1_2117 2117 > $T/gen2117.log 2>&1
$S/run.sh $T/base h2117m_semantic $T/t1_2117 semantic $T/cache_h_m
$S/run.sh $T/base h2117m_gt $T/t1_2117 gt $T/cache_h_m
$S/run.sh $T/new h2117n_semantic $T/t1_2117 semantic $T/cache_h_n
