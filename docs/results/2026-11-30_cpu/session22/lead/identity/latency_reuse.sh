#!/bin/bash
# latency_reuse.sh SRC BASE OUT RUNS: benchmarks/photo_latency.py --fills rays --threads 1 --reuse-source (one source
# state per frame, as the editor keeps it) of the code in SRC against main at the session start (BASE:
# session_start=BASE/src), the two codes' workers taking turns edit by edit (the 14 edits of session 14's 1242x375
# latency tree), RUNS times; each run into OUT/t1_rN.{txt,json}, the loads into OUT/latency_loads.txt. Pair them with
# docs/results/2026-11-30_cpu/session20/tcost/paired_kinds.py OUT/t1_r*.json.
set -u
S=$1; B=$2; O=$3; N=$4; mkdir -p $O
for r in $(seq 1 $N); do
  echo "r$r start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/latency_loads.txt
  (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python /work/main/benchmarks/photo_latency.py \
    --data /tmp/s22data/lead/latency_tree --fills rays --threads 1 --reuse-source --against session_start=$B/src \
    --json $O/t1_r$r.json > $O/t1_r$r.txt 2>&1)
  echo "r$r end $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/latency_loads.txt
done
