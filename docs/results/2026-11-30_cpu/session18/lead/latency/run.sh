#!/bin/bash
# run.sh: benchmarks/photo_latency.py on session 14's 1242x375 latency tree, this session's final code against the
# session start (5df87a1, a git archive), the codes taking turns edit by edit; 3 runs at threads 1, then 3 at threads 2.
cd /work/main
D=docs/results/2026-11-30_cpu/session18/lead/latency
for T in 1 2; do for R in 1 2 3; do
  OMP_NUM_THREADS=$T .venv/bin/python benchmarks/photo_latency.py --data /tmp/s14data/cost/vkitti --fills rays --threads $T \
    --against session_start=/tmp/s18data/lead/base_5df/src --json $D/t${T}_r$R.json > $D/t${T}_r$R.txt 2>&1
  echo "t$T r$R rc=$? $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $D/runs.log
done; done
