#!/bin/bash
# held2209.sh: the held-out check (run once, after the code was final and committed, d2df615): generate Table 1 tree
# 2209 with main's generator (session 9 fogflip's gen_t1.py), then the pose tables of main (9b7f993) and the branch
# (d2df615), then Table 1's predicted row of both. Logs to /tmp/s22data/fitcost2/held2209.log.
F=/tmp/s22data/fitcost2; M=$F/main_9b7; B=$F/trees/final; S=$(cd "$(dirname "$0")" && pwd)
GEN=/work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py
env -u PYTHONDONTWRITEBYTECODE PYTHONPATH=$M/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $GEN \
  $F/trees/t1_2209 2209 > $F/gen2209.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $F/held2209.log
$S/pose.sh $M $F/trees/t1_2209 $F/pose/h2209_main.json gt_fit pred_fit &
$S/pose.sh $B $F/trees/t1_2209 $F/pose/h2209_br.json gt_fit pred_fit &
wait
echo "pose $(date -u +%T)" >> $F/held2209.log
$S/t1.sh $M main 2209 &
$S/t1.sh $B br 2209 &
wait
echo "all $(date -u +%T)" >> $F/held2209.log
