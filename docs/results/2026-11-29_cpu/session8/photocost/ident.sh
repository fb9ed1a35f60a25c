#!/bin/bash
# ident.sh: lat3 replay with this worktree's code, compared to main's
cd /work/wt/s8-photocost && rm -rf /tmp/s8data/photocost/rep_new && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python docs/results/2026-11-29_cpu/session8/photocost/replay_photo.py /tmp/s8data/photocost/rep_new --lat /tmp/s5data/deletes/lat3 "$@" 2>&1 | tail -14 | awk '{printf "%s %s | ", $1, $2}'; echo; /work/main/.venv/bin/python docs/results/2026-11-29_cpu/session8/photocost/replay_photo.py --compare /tmp/s8data/photocost/rep_main /tmp/s8data/photocost/rep_new
