#!/bin/bash
# jtime.sh OUT ROUNDS: main's tree and the branch's alternated ROUNDS times (main, branch, main, ...), each a fresh
# process running jtime.py with 3 timed de-renders per joined frame; JSON lines appended to OUT (session 29 joincost29).
# EXTRA: more NAME:TREE pairs in each round (e.g. nojoin:/tmp/s29/joincost29/branch1: the frames without their join).
OUT=$1; ROUNDS=${2:-5}; HERE=$(cd "$(dirname "$0")" && pwd)
for r in $(seq $ROUNDS); do
  for C in main:/tmp/s29/joincost29/base branch:/tmp/s29/joincost29/branch1 ${EXTRA:-}; do
    (cd /tmp/s29/joincost29 && PYTHONPATH=${C#*:}/src SDN3D_CONFIG_DIR=${C#*:}/conf OMP_NUM_THREADS=1 nice -n 5 \
       /work/main/.venv/bin/python $HERE/jtime.py ${C%%:*} 3 >> $OUT 2>/dev/null)
  done
done
