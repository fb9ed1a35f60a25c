#!/bin/bash
# run.sh: benchmarks/photo_latency.py on session 14's 1242x375 latency tree, the final code's default fill (rays with
# photo.ray_vanishing=telea, helper erase) against the same code with ray_vanishing=near (the session start's rays),
# side by side in one process, edit by edit; 3 runs at threads 1 on the idle machine (vanishing_idle_r*.json).
cd /work/main
D=docs/results/2026-11-30_cpu/session19/lead/latency
for R in 1 2 3; do
  OMP_NUM_THREADS=1 .venv/bin/python benchmarks/photo_latency.py --data /tmp/s14data/cost/vkitti --fills rays \
    --variant near:fill=rays,ray_vanishing=near --threads 1 --json $D/vanishing_idle_r$R.json > $D/vanishing_idle_r$R.txt 2>&1
  echo "r$R rc=$? $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $D/runs.log
done
