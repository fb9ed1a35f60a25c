#!/bin/bash
# rounds.sh NEW BASE OUT [ROUNDS] [THREADS]: session14/cost/draw_edits.py's 14 latency edits (fill rays, a fresh
# source per edit) with this branch's code (NEW, a git archive) and main's (BASE), alternating process by process,
# ROUNDS rounds each, at THREADS torch threads; each edit's CPU and wall ms to OUT/{new,base}_R.txt and the load
# to OUT/load.txt. session14/cost/min_rounds.py OUT pairs them (the least of the rounds per edit).
set -u
NEW=$1; BASE=$2; O=$3; N=${4:-3}; T=${5:-1}; mkdir -p $O
DRAW=$NEW/docs/results/2026-11-29_cpu/session14/cost/draw_edits.py; TREE=/tmp/s14data/cost/vkitti
uptime > $O/load.txt
for r in $(seq 1 $N); do for C in new:$NEW base:$BASE; do S=${C#*:}; L=${C%%:*}
  PYTHONPATH=$S/src OMP_NUM_THREADS=$T nice -n 5 /work/main/.venv/bin/python $DRAW $TREE $O/${L}_$r --threads $T \
    > $O/${L}_$r.txt 2>&1
done; uptime >> $O/load.txt; done
