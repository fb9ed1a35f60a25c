# Held-out seed 2057 (generated here, like fit_cost.py's dense tree): cost before/after interleaved, then pose tables.
set -x
C=/tmp/s4data/cost; D=$C/dense2057; A=$C/after; B=$C/base
G=/tmp/h5runs/big_mb40/checkpoints/inference.pt
PY=/work/main/.venv/bin/python
cd $A && uptime && PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/fit_cost.py --geometric $G --data $D --seed 2057 --repeats 2 --out $C/h2057_cost_after1.json > /dev/null
# pose tables (oracle GT masks + boxes), before and after, in the background
cd $B && (PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric /tmp/h5runs/big_mb40/checkpoints/last.ckpt --data-root $D --part all --max-frames 0 --threads 1 --out $C/h2057_pose_before.json > $C/h2057_pose_before.log 2>&1 &)
cd $A && (PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric /tmp/h5runs/big_mb40/checkpoints/last.ckpt --data-root $D --part all --max-frames 0 --threads 1 --out $C/h2057_pose_after.json > $C/h2057_pose_after.log 2>&1 &)
for i in 1 2; do
  uptime
  cd $B && PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1 $PY benchmarks/fit_cost.py --geometric $G --data $D --repeats 2 --out $C/h2057_cost_before$i.json > /dev/null
  uptime
  cd $A && PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/fit_cost.py --geometric $G --data $D --repeats 2 --out $C/h2057_cost_after$((i+1)).json > /dev/null
done
uptime
echo done
