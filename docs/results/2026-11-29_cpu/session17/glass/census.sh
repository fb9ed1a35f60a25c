#!/bin/bash
# census.sh CODE_DIR NAME: session 14's probe.py (per pair: squared error split by part and source code, npz for
# pictures) on the tuning trees cf31 and cf33, turns of 45 and 90 degrees, ground-truth geometry (oracle), with the
# code at CODE_DIR; outputs under /tmp/s17data/glass/census_NAME/{cf31,cf33}_{45,90}.
set -u
S=$1; N=$2; O=/tmp/s17data/glass/census_$N; mkdir -p $O
R=$(cd "$(dirname "$0")/../../.." && pwd)
P=$R/2026-11-29_cpu/session14/ends/probe.py
declare -A TREES=([cf31]=/tmp/s11data/lead/cf31 [cf33]=/tmp/s14data/ends/cf33)
for T in cf31 cf33; do
  for B in 45 90; do
    (cd "$S" && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $P ${TREES[$T]} \
      $O/${T}_$B "turn $B" oracle > $O/${T}_$B.log 2>&1)
    echo "$T $B rc=$? $(date -u +%T)" >> $O/done.log
  done
done
