#!/bin/bash
cd /work/main
OMP_NUM_THREADS=1 nice -n 5 .venv/bin/python docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py /tmp/s21data/trees/t1_2193 2193 > /tmp/s21data/lead/gen2193.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> /tmp/s21data/lead/held2193.log
T=docs/results/2026-11-30_cpu/session21/lead/rows/t1.sh
CACHE_TAG=main $T /tmp/s21data/lead/code_9ed55bc final 2193 &
CACHE_TAG=base $T /tmp/s21data/lead/base_ea2 base 2193 &
wait
echo "all $(date -u +%T)" >> /tmp/s21data/lead/held2193.log
