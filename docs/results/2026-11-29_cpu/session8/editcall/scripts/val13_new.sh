#!/bin/bash
# val13 pose table, the final kernel (face groups per mesh), threads 1.
CK=/tmp/s5data/lead/demo/runs/geometric/checkpoints/best-epoch009.ckpt; PY=/work/main/.venv/bin/python
O=/tmp/s8data/editcall/val13; export SDN3D_NATIVE_CACHE=/tmp/s8data/editcall/native OMP_NUM_THREADS=1
T=/tmp/s8data/editcall/final; rm -rf $T; mkdir -p $T; git -C /work/wt/s8-editcall archive HEAD | tar x -C $T
cd $T && PYTHONPATH=$T/src:$T /usr/bin/time -v $PY benchmarks/pose_table.py --geometric $CK --data-root /tmp/s3data/val13 --part all --max-frames 40 --threads 1 --image-size 312 96 --min-pixels 64 --rows gt_branch gt_fit --crops photo --out $O/new.json > $O/new.log 2>&1
