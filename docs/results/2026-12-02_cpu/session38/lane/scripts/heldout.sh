#!/bin/bash
# heldout.sh OUT SEEDS...: PLAN.md's runs: per held-out tree (/tmp/trees/h$SEED), Table 1's predicted row and the pose
# table, arm main (worktree /work/wt_base) and arm lane (/work/wt_prior), the two arms side by side.
OUT=$1; shift
W=${W:-/tmp/w38}
mkdir -p $OUT
t1() {  # t1 ARM TREE SEED
  PYTHONPATH=$2/src /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=/tmp/trees/h$3 'data.image_size=[312,96]' \
    run=$W/outputs/demo 'compose=[photo]' "proposals=[semantic]" scene=derender threads=1 examples=0 \
    output_dir=$OUT/$3_$1 > $OUT/t1_$3_$1.log 2>&1
}
pose() {  # pose ARM TREE SEED
  PYTHONPATH=$2/src /work/main/.venv/bin/python $2/benchmarks/pose_table.py \
    --geometric $W/outputs/demo/runs/geometric/checkpoints/inference.pt \
    --semantic $W/outputs/demo/runs/semantic/checkpoints/inference.pt --data-root /tmp/trees/h$3 --part all \
    --max-frames 40 --threads 1 --image-size 312 96 --rows gt_fit pred_fit --out $OUT/pose_$3_$1.json \
    > $OUT/pose_$3_$1.log 2>&1
}
for s in "$@"; do
  while [ ! -f /tmp/trees/h$s/_SUCCESS ]; do sleep 10; done
  t1 main /work/wt_base $s & t1 lane /work/wt_prior $s; wait
  pose main /work/wt_base $s & pose lane /work/wt_prior $s; wait
  echo "tree $s done $(date +%T)"
done
