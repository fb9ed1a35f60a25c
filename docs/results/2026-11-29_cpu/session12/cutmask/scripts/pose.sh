#!/bin/bash
# Pose table of one tree with one code tree (issue 40): benchmarks/pose_table.py, 40 frames, 312x96, photo crops,
# threads 1, the demo's weights.  usage: pose.sh TREE DATA OUT.json ROWS... [-- --fit KEY=VALUE ...]
# TREE: a checkout whose library (TREE/src) is measured (main's git archive or this worktree); the table script is
# this worktree's (BENCH: it records each object's template and length error); DATA: a generated tree; ROWS:
# pose_table's --rows keys.
RUNS=${RUNS:-/tmp/s11data/demo/out/runs}; PY=/work/main/.venv/bin/python
BENCH=${BENCH:-$1/benchmarks/pose_table.py}  # the measured tree's own pose table
T=$1; DATA=$2; OUT=$3; shift 3
ROWS=(); while [ $# -gt 0 ] && [ "$1" != "--" ]; do ROWS+=("$1"); shift; done; [ "$1" = "--" ] && shift
CK=$(ls $RUNS/geometric/checkpoints/best-*.ckpt | head -1)
SEM=""  # the semantic branch only for the predicted proposals' rows (its finished run's best checkpoint)
case " ${ROWS[*]}" in *" pred_"*) SEM=$(ls $RUNS/semantic/checkpoints/best-*.ckpt | head -1);; esac
cd "$T" && PYTHONPATH=$T/src:$T OMP_NUM_THREADS=1 nice -n 5 $PY "$BENCH" --geometric "$CK" \
  ${SEM:+--semantic "$SEM"} --data-root "$DATA" --part all --max-frames 40 --threads 1 --image-size 312 96 \
  --min-pixels 64 --rows "${ROWS[@]}" --crops photo --out "$OUT" "$@"
