#!/bin/bash
# pose.sh CODE DATA OUT.json ROWS... [-- KEY=VALUE...]: benchmarks/pose_table.py of the code tree CODE (a git archive
# or worktree with src and benchmarks) on the tree DATA: 40 frames, 312x96, photo crops, threads 1, session 21's demo
# weights (w0); ROWS: pose_table's --rows keys; after --, FitSettings overrides (--fit). Session 22 fitcost's pose.sh
# with this helper's folders; appends "NAME rc=... time" to /tmp/s22data/fitcost2/pose/done.log.
T=$1; DATA=$2; OUT=$3; shift 3
ROWS=(); while [ $# -gt 0 ] && [ "$1" != "--" ]; do ROWS+=("$1"); shift; done; [ "$1" = "--" ] && shift
FIT=(); [ $# -gt 0 ] && FIT=(--fit "$@")
W=/tmp/s21data/demo/out/runs
cd "$T" && env -u PYTHONDONTWRITEBYTECODE PYTHONPATH=$T/src:$T OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  benchmarks/pose_table.py --geometric $W/geometric/checkpoints/best-epoch009.ckpt \
  --semantic $W/semantic/checkpoints/best-epoch013.ckpt --data-root "$DATA" --part all \
  --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 --rows "${ROWS[@]}" --crops photo "${FIT[@]}" \
  --out "$OUT" > "${OUT%.json}.log" 2>&1
echo "$(basename "$OUT") rc=$? $(date -u +%T)" >> /tmp/s22data/fitcost2/pose/done.log
