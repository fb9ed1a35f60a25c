#!/bin/bash
# tuning.sh CODE NAME SOURCE: probe.sh (sdn3d-bench's counterfactual turn benchmark, fill rays, unchanged, with the
# error recorded by source code and part) of the code tree CODE on the three tuning trees cf31, cf33, cf39
# (/tmp/s21data/trees, session 21's generator), source scene SOURCE (oracle or semantic); outputs
# /tmp/s25data/back41/bench/NAME_cf3X_SOURCE{,.pt,.log}. Main: CODE=/tmp/s25data/lead/base_9a6 NAME=main; the branch:
# a git archive of its commit. Run one per source, both at once; then turns.py and where.py.
HERE=$(cd "$(dirname "$0")" && pwd)
for t in cf31 cf33 cf39; do
  bash "$HERE/probe.sh" "$1" /tmp/s21data/trees/$t /tmp/s25data/back41/bench/$2_${t}_$3 "$3"
done
