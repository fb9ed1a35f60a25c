#!/bin/bash
# latency.sh SRC OUT RUNS: benchmarks/photo_latency.py --fills rays --threads 1 of the code in SRC (a git archive of
# this branch) against main at the session's start (session_start=/tmp/s18data/lead/base_5df/src), the two codes in
# worker processes taking turns edit by edit (14 edits of the 1242x375 latency tree), RUNS times; each run's table
# and JSON into OUT/t1_rN.{txt,json}, the load before and after each into OUT/latency_loads.txt. Pair them with
# session15/lead/latency/paired.py (run in OUT).
set -u
S=$1; O=$2; N=$3; mkdir -p $O
for r in $(seq 1 $N); do
  echo "r$r start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/latency_loads.txt
  (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python benchmarks/photo_latency.py \
    --data /tmp/s14data/cost/vkitti --fills rays --threads 1 --against session_start=/tmp/s18data/lead/base_5df/src \
    --json $O/t1_r$r.json > $O/t1_r$r.txt 2>&1)
  echo "r$r end $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/latency_loads.txt
done
