#!/bin/bash
for S in 2285 2287 2289; do
  /usr/bin/time -v env OMP_NUM_THREADS=1 PYTHONPATH=/tmp/s30/t1big30/base/src:/tmp/s30/t1big30/base nice -n 5 /work/main/.venv/bin/python /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py /tmp/s30/t1big30/trees/t1_$S $S > logs/gen_$S.log 2>&1
  echo "gen $S rc=$? $(date -u +%T)" >> logs/gen.log
done
