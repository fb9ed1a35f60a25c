#!/bin/bash
# poses.sh SEED...: session 13 rotloss's poses.py on main's and the branch's Table 1 runs of each seed and row (main:
# session 17's rows runs for 31/35/37, else /tmp/s18data/pick/t1/main<SEED>; the branch: /tmp/s18data/pick/t1/pick<SEED>),
# with the shared de-render cache; JSON in /tmp/s18data/pick/poses/{main,pick}<SEED>_<row>.json. Run from the worktree
# (its src on PYTHONPATH: poses.py only reads the runs, the cache and the trees).
POSES=/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/poses.py; T=/tmp/s18data/pick/t1
for SEED in "$@"; do
  case $SEED in 31) TREE=/tmp/s11data/lead/t1_31;; 35|37) TREE=/tmp/s11data/semrain/t1_$SEED;; *) TREE=/tmp/s18data/pick/t1_$SEED;; esac
  for P in semantic gt; do
    case $SEED in 31|35|37) MAIN=/tmp/s17data/lead/t1/rows${SEED}_$P;; *) MAIN=$T/main${SEED}_$P;; esac
    for ARM in main pick; do
      [ $ARM = main ] && RUN=$MAIN || RUN=$T/pick${SEED}_$P
      PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $POSES $RUN $RUN.dump $T/cache$SEED $TREE \
        /tmp/s18data/pick/poses/$ARM${SEED}_$P.json > /tmp/s18data/pick/poses/$ARM${SEED}_$P.log 2>&1
      echo "poses $ARM $SEED $P rc=$? $(date -u +%T)"
    done
  done
done
