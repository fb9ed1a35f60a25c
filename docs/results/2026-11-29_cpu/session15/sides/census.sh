#!/bin/bash
# census.sh CODE_DIR NAME: probe.py (session 14 ends) on cf31/cf33 oracle 45 and 90 bins
S=$1; N=$2; O=/tmp/s15data/sides/census_$N; mkdir -p $O
P=/work/wt/sides/docs/results/2026-11-29_cpu/session14/ends/probe.py
for T in cf31 cf33; do [ $T = cf31 ] && TREE=/tmp/s11data/lead/cf31 || TREE=/tmp/s14data/ends/cf33
 for B in 45 90; do
  (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $P $TREE $O/${T}_$B "turn $B" oracle > $O/${T}_$B.log 2>&1)
  echo "$T $B rc=$? $(date -u +%T)" >> $O/done.log
 done; done
