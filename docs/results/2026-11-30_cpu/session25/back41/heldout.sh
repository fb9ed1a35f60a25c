#!/bin/bash
# heldout.sh SOURCE: the held-out tree 2239 (made once by gen.sh below), measured once with probe.sh: main 9a61b5b
# (/tmp/s25data/lead/base_9a6) then the branch's final code (/tmp/s25data/back41/br_final, a git archive of
# 5c1e23e), source scene SOURCE (oracle or semantic); outputs /tmp/s25data/back41/bench/ho_{main,branch}_cf2239_SOURCE.
# Run one per source, both at once; then turns.py, perpair.py.
# The tree (main's generator, session 5's recipe), made once before:
#   cd /tmp/s25data/lead/base_9a6 && PYTHONPATH=src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
#     /work/wt/back41/docs/results/2026-11-28_cpu/session5/turns/gen_cf.py /tmp/s25data/back41/cf2239 2239 \
#     0006,0018,0020 6
HERE=$(cd "$(dirname "$0")" && pwd)
T=/tmp/s25data/back41/cf2239; B=/tmp/s25data/back41/bench
bash "$HERE/probe.sh" /tmp/s25data/lead/base_9a6 $T $B/ho_main_cf2239_$1 $1
bash "$HERE/probe.sh" /tmp/s25data/back41/br_final $T $B/ho_branch_cf2239_$1 $1
