#!/bin/bash
# latency.sh NEW BASE OUT RUNS: benchmarks/photo_latency.py --fills rays on session 14's 1242x375 latency tree, this
# branch's code (NEW, a git archive) against main's (BASE: --against main=BASE/src), at threads 1 and 2 in
# alternation, RUNS runs each; per run its table (.txt, the load before and after) and per-edit times (.json), which
# session14/cost/paired_latency.py pairs.
set -u
NEW=$1; BASE=$2; mkdir -p $3; O=$(cd "$3" && pwd); N=${4:-2}
for r in $(seq 1 $N); do for T in 1 2; do F=$O/photo_latency_t${T}_run$r
  { echo "load before: $(uptime)"
    (cd $NEW && PYTHONPATH=$NEW/src OMP_NUM_THREADS=$T nice -n 5 /work/main/.venv/bin/python \
      benchmarks/photo_latency.py --data /tmp/s14data/cost/vkitti --fills rays --threads $T \
      --against main=$BASE/src --json $F.json) 2>&1
    echo "load after: $(uptime)"; } > $F.txt
done; done
