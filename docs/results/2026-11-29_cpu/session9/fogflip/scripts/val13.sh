#!/bin/bash
# val13 pose table (seed 13 tuning tree, clear weather), fit row: base (main fc689d8) and new (this branch), side by side.
CK=/tmp/s5data/lead/demo/runs/geometric/checkpoints/best-epoch009.ckpt; PY=/work/main/.venv/bin/python
O=/tmp/s9data/fogflip/val13; export SDN3D_NATIVE_CACHE=/tmp/s9data/fogflip/native OMP_NUM_THREADS=1
for side in base new; do
  T=/tmp/s9data/fogflip/$side
  ( cd $T && PYTHONPATH=$T/src:$T /usr/bin/time -v $PY benchmarks/pose_table.py --geometric $CK --data-root /tmp/s3data/val13 --part all --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 --rows gt_branch gt_fit --crops photo --out $O/$side.json > $O/$side.log 2>&1 ) &
done
wait
