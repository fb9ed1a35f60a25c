#!/bin/bash
# run.sh OUT REPS: editor_turns.py for both cars, main at the session start (/tmp/s22data/lead/base_1e2) and the
# candidate (/tmp/s22data/lead/cand), taking turns REPS times; JSON per run into OUT.
set -u
O=$1; N=$2; mkdir -p $O; D=$(cd "$(dirname "$0")" && pwd)
for r in $(seq 1 $N); do for id in 12001 12002; do for c in base:/tmp/s22data/lead/base_1e2 cand:/tmp/s22data/lead/cand; do
  (cd ${c#*:} && PYTHONPATH=${c#*:}/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $D/editor_turns.py \
    /tmp/s21data/demo/out/runs $id > $O/${c%%:*}_${id}_r$r.json 2> $O/${c%%:*}_${id}_r$r.log)
done; done; done
