W=/tmp/w36/outputs/demo/runs
for S in "$@"; do
  PYTHONPATH=/work/main/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /work/main/benchmarks/pose_table.py --geometric $W/geometric/checkpoints/inference.pt \
    --semantic $W/semantic/checkpoints/inference.pt --data-root /tmp/s36/t1_$S --part all --max-frames 40 --threads 1 \
    --image-size 312 96 --rows pred_fit --out /tmp/s36/impl/impl_$S.json > /tmp/s36/impl/impl_$S.log 2>&1
  echo "$S rc=$?" >> /tmp/s36/impl/log.txt
done
