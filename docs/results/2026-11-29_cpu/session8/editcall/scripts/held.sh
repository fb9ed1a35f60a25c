#!/bin/bash
# Held-out seed 2089, generated after the code was final: val13's generator (/tmp/s3data/gen_val13.py) with seed 2089,
# then val13's pose-table command on it, before (base fc6b2b7) and after (this branch's final tree), side by side.
O=/tmp/s8data/editcall; PY=/work/main/.venv/bin/python; D=$O/val2089; H=$O/held2089; mkdir -p $H
CK=/tmp/s5data/lead/demo/runs/geometric/checkpoints/best-epoch009.ckpt
uptime
sed -e 's#/tmp/s3data/val13#'$D'#' -e 's/seed=13/seed=2089/' /tmp/s3data/gen_val13.py > $O/gen_val2089.py
cd $O/final && PYTHONPATH=$O/final/src OMP_NUM_THREADS=1 $PY $O/gen_val2089.py > $H/gen.log 2>&1
uptime
export SDN3D_NATIVE_CACHE=$O/native OMP_NUM_THREADS=1
for side in base final; do
  T=$O/$side
  ( cd $T && PYTHONPATH=$T/src:$T $PY benchmarks/pose_table.py --geometric $CK --data-root $D --part all --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 --rows gt_branch gt_fit --crops photo --out $H/$side.json > $H/$side.log 2>&1 ) &
done
wait
uptime
