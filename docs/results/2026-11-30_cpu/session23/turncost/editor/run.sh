#!/bin/bash
# run.sh OUT REPS: editor_turns.py (the real frame, one EditSession, a car turned 15, 30, ..., 180 degrees) for both
# cars, main 73c0792 (/tmp/s23data/lead/base_73c, "base") and the branch (CAND: default /tmp/s23data/turncost/code_fin,
# a git archive of 0478469; the k-d tree run used CAND=/tmp/s23data/turncost/code_kd, of 3bb359b; "cand"), taking
# turns REPS times; JSON per run into OUT (session 22 lead's run.sh, session 23's paths).
# Pair them with paired.py OUT.
set -u
CAND=${CAND:-/tmp/s23data/turncost/code_fin}
O=$1; N=$2; mkdir -p $O; D=$(cd "$(dirname "$0")" && pwd)
for r in $(seq 1 $N); do for id in 12001 12002; do for c in base:/tmp/s23data/lead/base_73c cand:$CAND; do
  echo "${c%%:*} $id r$r start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/loads.txt
  (cd ${c#*:} && PYTHONPATH=${c#*:}/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $D/editor_turns.py \
    /tmp/s21data/demo/out/runs $id > $O/${c%%:*}_${id}_r$r.json 2> $O/${c%%:*}_${id}_r$r.log)
done; done; done
