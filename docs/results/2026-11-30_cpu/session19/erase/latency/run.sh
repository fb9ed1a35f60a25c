#!/bin/bash
# run.sh: benchmarks/photo_latency.py on session 14's 1242x375 latency tree (/tmp/s14data/cost/vkitti), the branch's
# final code (a git archive of 6d1ee02) against main (d47d803, /tmp/s19data/lead/base_d47), the codes in worker
# processes taking turns edit by edit (the same load); fill rays, threads 1; runs named by the arguments (default 1 2; run 3 was made later by `run.sh 3`).
D=/work/wt/erase/docs/results/2026-11-30_cpu/session19/erase/latency
cd /tmp/s19data/erase/br_6d1 || exit 1
for R in ${@:-1 2}; do
  PYTHONPATH=/tmp/s19data/erase/br_6d1/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python benchmarks/photo_latency.py \
    --data /tmp/s14data/cost/vkitti --fills rays --threads 1 --against main=/tmp/s19data/lead/base_d47/src \
    --json $D/t1_r$R.json > $D/t1_r$R.txt 2>&1
  echo "t1 r$R rc=$? $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $D/runs.log
done
