# heldout.sh SEED: generate held-out tree SEED once (session 9's gen_t1.py), then row pred_fit with main (SOFT=0) and
# the candidate (MODE=ignore, 0.3-0.7) through posesoft.py, w36, main 5d254108's code
set -u
S=$1; T=/tmp/s36/unsure/t1_$S; O=/tmp/s36/unsure; W=/tmp/w36/outputs/demo/runs; mkdir -p $O
[ -e $T ] && { echo "tree $T exists: one generation only" >&2; exit 3; }
export PYTHONPATH=/tmp/s36_lead_base/src OMP_NUM_THREADS=1
/work/main/.venv/bin/python /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T $S > $O/gen_$S.log 2>&1
for V in main ign37; do
  [ $V = main ] && { SOFT=0; MODE=; } || { SOFT=1; MODE=ignore; }
  SOFT=$SOFT SOFT_MODE=$MODE SOFT_LO=0.3 SOFT_HI=0.7 /work/main/.venv/bin/python /tmp/s36/soft/posesoft.py \
    --geometric $W/geometric/checkpoints/inference.pt --semantic $W/semantic/checkpoints/inference.pt --data-root $T \
    --part all --max-frames 40 --threads 1 --image-size 312 96 --rows pred_fit --out $O/${V}_$S.json > $O/${V}_$S.log 2>&1
  echo "$S $V rc=$? $(date -u +%T)" >> $O/log.txt
done
