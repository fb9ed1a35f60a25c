#!/bin/bash
# held.sh: held-out seed 2115, generated after the code was final (gen_t1.py of session9/fogflip, as the tuning
# trees), measured once: main's Table 1 photo rows, semantic proposals then ground-truth masks (oracle), with the
# fresh demo weights; one de-render cache for the seed
B=/tmp/s11data/semrain/base; T=/tmp/s11data/semrain; W=/work/wt/semrain
S=$W/docs/results/2026-11-29_cpu/session11/semrain/scripts
while pgrep -f "runs/gMV35_semantic.dump" > /dev/null; do sleep 5; done
cd $W && PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T/t1_2115 2115 > $T/gen2115.log 2>&1
$S/run.sh $B h2115_semantic $T/t1_2115 semantic $T/cache_h_2115
$S/run.sh $B h2115_gt $T/t1_2115 gt $T/cache_h_2115
