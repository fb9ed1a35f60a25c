#!/bin/bash
# latency.sh CAND OUT RUNS: benchmarks/photo_latency.py --fills rays --threads 1 (a fresh source per edit) of the
# branch (CAND, a git archive of it; column "this") against main 9a61b5b (/tmp/s25data/lead/base_9a6, column
# "session_start"), the two codes in worker processes taking turns edit by edit on the 14 edits of session 14's
# 1242x375 latency tree (/tmp/s22data/lead/latency_tree), RUNS times (session 23 turncost's latency.sh, this
# session's paths); REUSE=1: with --reuse-source (one source state per frame). Pair them with paired_kinds.py
# OUT/t1_r*.json.
set -u
S=$1; O=$2; N=$3; mkdir -p $O; B=/tmp/s25data/lead/base_9a6
for r in $(seq 1 $N); do
  echo "r$r start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/latency_loads.txt
  (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python benchmarks/photo_latency.py \
    --data /tmp/s22data/lead/latency_tree --fills rays --threads 1 --against session_start=$B/src ${REUSE:+--reuse-source} \
    --json $O/t1_r$r.json > $O/t1_r$r.txt 2>&1)
  echo "r$r end $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/latency_loads.txt
done
