# Held-out seed 2063 (generated here by fit_cost.py like session 4's 2057): fit cost before/after alternating,
# pose tables before/after (background), then the sdn3d-edit call, threads=2, farm-bench alternating.
set -x
C=/tmp/s5data/cost; D=$C/dense2063; A=/work/wt/s5-cost; B=$C/main
G=/tmp/h5runs/big_mb40/checkpoints/inference.pt; PY=/work/main/.venv/bin/python
mkdir -p $C/held
cd $A && uptime && PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/fit_cost.py --geometric $G --data $D --seed 2063 --repeats 2 --out $C/held/cost_after1.json > /dev/null
cd $B && (PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric /tmp/h5runs/big_mb40/checkpoints/last.ckpt --data-root $D --part all --max-frames 0 --threads 1 --out $C/held/pose_before.json > $C/held/pose_before.log 2>&1 &)
cd $A && (PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/pose_table.py --geometric /tmp/h5runs/big_mb40/checkpoints/last.ckpt --data-root $D --part all --max-frames 0 --threads 1 --out $C/held/pose_after.json > $C/held/pose_after.log 2>&1 &)
for i in 1 2; do
  uptime
  cd $B && PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1 $PY benchmarks/fit_cost.py --geometric $G --data $D --repeats 2 --out $C/held/cost_before$i.json > /dev/null
  uptime
  cd $A && PYTHONPATH=$A/src:$A OMP_NUM_THREADS=1 $PY benchmarks/fit_cost.py --geometric $G --data $D --repeats 2 --out $C/held/cost_after$((i+1)).json > /dev/null
done
uptime
echo cost done
