#!/bin/bash
# real.sh NAME:SRC[,NAME:SRC...] OUT: the real frame of tests/data, each car turned 45/90/180, recoloured blue and
# deleted, by session 12's realframe/probe.py (one EditSession, the session 11 demo's weights, session 4's boxes),
# once per code (SRC: a git archive or a copy of the code; NAME: the output folder's name).
set -u
CODES=${1//,/ }; O=$2; mkdir -p $O
R=$(cd "$(dirname "$0")/../.." && pwd)
for C in $CODES; do
  S=${C#*:}; N=${C%%:*}
  (cd $S && PYTHONPATH=$S/src:$S OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $R/session12/realframe/probe.py /tmp/s11data/demo/out/runs $O/$N > $O/$N.log 2>&1)
  echo "real $N rc=$? $(date -u +%T)" >> $O/real.log
done
