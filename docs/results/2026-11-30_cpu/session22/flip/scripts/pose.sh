#!/bin/bash
# Pose table of one tree with one code tree (issue 40): benchmarks/pose_table.py --part all, 40 frames, 312x96,
# photo crops, threads 1.  usage: pose.sh CODE DATA OUT.json [ROWS...]
# CODE: a tree whose library (CODE/src) and pose_table.py (CODE/benchmarks) are measured (main's plain tree
# /tmp/s22data/lead/base_1e2 or this worktree); DATA: a generated tree; ROWS (default gt_branch gt_fit pred_fit).
# env RUNS: the demo's runs folder (default w0, /tmp/s21data/demo/out/runs).
RUNS=${RUNS:-/tmp/s21data/demo/out/runs}; PY=/work/main/.venv/bin/python
T=$1; DATA=$2; OUT=$3; shift 3
ROWS=("$@"); [ ${#ROWS[@]} -eq 0 ] && ROWS=(gt_branch gt_fit pred_fit)
CK=$(ls $RUNS/geometric/checkpoints/best-*.ckpt | head -1)
SEM=$(ls $RUNS/semantic/checkpoints/best-*.ckpt | head -1)
cd "$T" && PYTHONPATH=$T/src:$T OMP_NUM_THREADS=1 nice -n 5 $PY benchmarks/pose_table.py --geometric "$CK" \
  --semantic "$SEM" --data-root "$DATA" --part all --max-frames 40 --threads 1 --image-size 312 96 \
  --min-pixels 64 --rows "${ROWS[@]}" --crops photo --out "$OUT"
