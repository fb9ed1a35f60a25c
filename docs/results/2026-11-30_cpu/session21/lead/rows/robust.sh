#!/bin/bash
cd /work/main
L=/tmp/s21data/lead/robust.log
(OMP_WAIT_POLICY=PASSIVE nice -n 5 .venv/bin/sdn3d-demo seed=1 output_dir=/tmp/s21data/demo1/out data_dir=/tmp/s21data/demo1/out/data > /tmp/s21data/lead/demo1.log 2>&1; echo "demo1 rc=$? $(date -u +%T)" >> $L) &
OMP_NUM_THREADS=1 nice -n 5 .venv/bin/python docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py /tmp/s21data/trees/t1_2195 2195 > /tmp/s21data/lead/gen2195.log 2>&1
echo "gen2195 rc=$? $(date -u +%T)" >> $L
T=docs/results/2026-11-30_cpu/session21/lead/rows/t1.sh
CACHE_TAG=main $T /tmp/s21data/lead/code_9ed55bc final 2195
wait
WEIGHTS=/tmp/s21data/demo1/out CACHE_TAG=w1 $T /tmp/s21data/lead/code_9ed55bc finalw1_ 2193 2195
echo "all $(date -u +%T)" >> $L
