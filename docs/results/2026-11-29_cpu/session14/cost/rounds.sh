#!/bin/bash
# rounds.sh OUT [ROUNDS]: draw_edits.py's 14 edits (fill rays, a fresh source state per edit, threads 1) with this
# branch's code (NEW, a git archive of it) and main's (BASE), alternating process by process, ROUNDS rounds each;
# (BASE env: another main archive); every edit's CPU and wall ms to OUT/{new,base}_R.txt (min_rounds.py pairs
# them, the least of the rounds per edit).
set -u
O=$1; N=${2:-3}; R=$(cd "$(dirname "$0")" && pwd); mkdir -p $O
NEW=/tmp/s14data/cost/new_tree; BASE=${BASE:-/tmp/s14data/cost/base}; TREE=/tmp/s14data/cost/vkitti
uptime > $O/load.txt
for r in $(seq 1 $N); do for C in new:$NEW base:$BASE; do S=${C#*:}; L=${C%%:*}
  PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $R/draw_edits.py $TREE $O/${L}_$r > $O/${L}_$r.txt 2>&1
done; uptime >> $O/load.txt; done
