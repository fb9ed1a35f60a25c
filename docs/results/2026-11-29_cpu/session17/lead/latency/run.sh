#!/bin/bash
# run.sh: benchmarks/photo_latency.py on session 14's 1242x375 latency tree, this session's final code against the
# session start (35b8cdf, a git archive), the codes taking turns edit by edit; 3 runs at threads 1, then 3 at threads 2.
cd /work/main
for T in 1 2; do for R in 1 2 3; do
  OMP_NUM_THREADS=$T .venv/bin/python benchmarks/photo_latency.py --data /tmp/s14data/cost/vkitti --fills rays --threads $T \
    --against session_start=/tmp/s17data/lead/base_35b/src --json docs/results/2026-11-29_cpu/session17/lead/latency/t${T}_r$R.json \
    > docs/results/2026-11-29_cpu/session17/lead/latency/t${T}_r$R.txt 2>&1
  echo "t$T r$R rc=$? $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> docs/results/2026-11-29_cpu/session17/lead/latency/runs.log
done; done
