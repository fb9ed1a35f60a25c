#!/bin/bash
# held.sh BRANCH_SRC: held-out seed 2185 (a counterfactual tree by session 5's recipe, main's generator), generated
# after the code was final, measured once: main ea2ed39 (/tmp/s21data/lead/base_ea2) against BRANCH_SRC (a git archive
# of the final commit), turns with ground-truth geometry (oracle) and predicted (this session's demo weights), the
# two codes side by side. Threads 1, nice 5; outputs under /tmp/s21data/cover/held.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
M=/tmp/s21data/lead/base_ea2; B=$1; O=/tmp/s21data/cover/held; T=/tmp/s21data/cover/cf2185
mkdir -p $O
if [ ! -f $T/_SUCCESS ]; then  # made once (10:32 UTC, main's generator)
  cd $M && PYTHONPATH=$M/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
    /work/wt/cover/docs/results/2026-11-28_cpu/session5/turns/gen_cf.py $T 2185 0006,0018,0020 6 > $O/gen.log 2>&1
  echo "gen rc=$? $(date -u +%T)"
fi
for SRC in oracle semantic; do
  $HERE/turns.sh $M $T $O/m_$SRC $SRC &
  $HERE/turns.sh $B $T $O/b_$SRC $SRC &
  wait
  echo "$SRC $(date -u +%T)"
done
