#!/bin/bash
# Held-out seed 2077, generated after the code was final (benchmarks/fit_cost.py --seed 2077, as session 5's 2063):
# pose tables before (base 5426919) and after (this branch), side by side. Oracle: ground-truth masks + boxes.
set -x
C=/tmp/s6data/cost; D=$C/dense2077; A=/work/wt/s6-cost; B=$C/base; H=$C/held2077
G=/tmp/h5runs/big_mb40/checkpoints/inference.pt; PY=/work/main/.venv/bin/python
mkdir -p $H
cd $A && uptime && PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/fit_cost.py --geometric $G --data $D --seed 2077 --repeats 1 --out $H/cost_after_gen.json > $H/gen.log 2>&1
cd $B && (PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric /tmp/h5runs/big_mb40/checkpoints/last.ckpt --data-root $D --part all --max-frames 0 --threads 1 --out $H/pose_before.json > $H/pose_before.log 2>&1 &)
cd $A && PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric /tmp/h5runs/big_mb40/checkpoints/last.ckpt --data-root $D --part all --max-frames 0 --threads 1 --out $H/pose_after.json > $H/pose_after.log 2>&1
uptime
