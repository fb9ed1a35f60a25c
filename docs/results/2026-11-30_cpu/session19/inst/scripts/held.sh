#!/bin/bash
# held.sh: the held-out seed 2167, generated once the code was final (the branch's commit in the README), then
# Table 1's two rows for main (/tmp/s19data/lead/base_d47) and for the branch (/work/wt/inst), each arm with its own
# de-render cache (t1.sh), then the proposal-recall inputs of its Table 1 source frames (raw.py).
S=/work/wt/inst/docs/results/2026-11-30_cpu/session19/inst/scripts
cd /work/wt/inst || exit 1
echo "gen 2167 start $(date -u +%T)" >> /tmp/s19data/inst/t1/t1.log
PYTHONPATH=/work/wt/inst/src:/work/wt/inst OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py /tmp/s19data/inst/t1_2167 2167 > /tmp/s19data/inst/gen2167.log 2>&1
echo "gen 2167 rc=$? $(date -u +%T)" >> /tmp/s19data/inst/t1/t1.log
$S/t1.sh /tmp/s19data/lead/base_d47 main 2167
$S/t1.sh /work/wt/inst inst 2167
PYTHONPATH=/work/wt/inst/src:/work/wt/inst OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $S/raw.py \
  /tmp/s19data/inst/t1_2167 312 96 /tmp/s19data/inst/raw2167_312.pt >> /tmp/s19data/inst/t1/t1.log 2>&1
