#!/bin/bash
# real.sh NAME:SRC[,NAME:SRC...] OUT: the real frame of tests/data, each car turned 45/90/180, recoloured blue and
# deleted, by session 12's probe.py (one EditSession: the pictures sdn3d-edit draws, one de-render for every edit; the
# session 11 demo's weights and session 4 real_strip.py's boxes), once per code; then session 12's strip.py and
# session 13's closeups.py (BEFORE = the first code, AFTER = the second).
set -u
CODES=${1//,/ }; O=$2; mkdir -p $O
R=/work/wt/ends/docs/results/2026-11-29_cpu
for C in $CODES; do
  S=${C#*:}; N=${C%%:*}
  (cd $S && PYTHONPATH=$S/src:$S OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $R/session12/realframe/probe.py /tmp/s11data/demo/out/runs $O/$N > $O/$N.log 2>&1)
  echo "real $N rc=$? $(date -u +%T)" >> $O/real.log
done
