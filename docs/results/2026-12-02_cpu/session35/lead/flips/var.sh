# var.sh TAG LAMPCUE SEEDS...: pose rows gt_fit + pred_fit on tuning trees (generated if missing)
set -u
TAG=$1; LC=$2; shift 2
cd /work/main
for S in "$@"; do
  T=/tmp/s35/tune/t1_$S
  [ -e $T/_SUCCESS ] || { rm -rf $T; OMP_NUM_THREADS=1 .venv/bin/python docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T $S > /tmp/s35/tune/gen_$S.log 2>&1; }
  LAMPCUE=$LC OMP_NUM_THREADS=1 .venv/bin/python /tmp/s35/tune/posevar35.py --geometric /tmp/w35/outputs/demo/runs/geometric/checkpoints/inference.pt \
    --semantic /tmp/w35/outputs/demo/runs/semantic/checkpoints/inference.pt --data-root $T --part all --max-frames 40 --threads 1 \
    --image-size 312 96 --rows gt_fit pred_fit --out /tmp/s35/tune/${TAG}_$S.json > /tmp/s35/tune/${TAG}_$S.log 2>&1
  echo "$TAG $S rc=$? $(date -u +%T)" >> /tmp/s35/tune/log.txt
done
