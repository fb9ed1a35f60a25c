# var.sh TAG SOFT [POWER]: pred_fit on the tuning trees with posesoft.py (main 5d254108 worktree code)
set -u
TAG=$1; SOFT=$2; POW=${3:-1}; W=/tmp/w36/outputs/demo/runs
for S in 35 37 39 41 43; do
  SOFT=$SOFT SOFT_POWER=$POW SOFT_MODE=${MODE:-} SOFT_LO=${LO:-0.3} SOFT_HI=${HI:-0.7} SOFT_CAP=${CAP:-} SOFT_MODE=${MODE:-} SOFT_LO=${LO:-0.3} SOFT_HI=${HI:-0.7} PYTHONPATH=/tmp/s36_lead_base/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s36/soft/posesoft.py --geometric $W/geometric/checkpoints/inference.pt \
    --semantic $W/semantic/checkpoints/inference.pt --data-root /tmp/s36/t1_$S --part all --max-frames 40 --threads 1 \
    --image-size 312 96 --rows pred_fit --out /tmp/s36/soft/${TAG}_$S.json > /tmp/s36/soft/${TAG}_$S.log 2>&1
  echo "$TAG $S rc=$? $(date -u +%T)" >> /tmp/s36/soft/log.txt
done
