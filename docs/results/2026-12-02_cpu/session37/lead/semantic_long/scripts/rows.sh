#!/usr/bin/env bash
# rows.sh TREE OUT ARM [ROW]: sdn3d-bench's Table 1 photo row ROW (semantic = predicted, default; gt = ground-truth
# masks, an oracle) at 312x96 on TREE with the run root of ARM (w37: the demo's; B, A: w37's geometric and textural
# branches with the arm's semantic run, /tmp/s37/sem{B,A}); one thread. Code: main at this session's start (a worktree).
set -u
TREE=$1; OUT=$2; ARM=$3; ROW=${4:-semantic}; CODE=/tmp/s37_base
if [ "$ARM" = w37 ]; then W=/tmp/w37/outputs/demo; else
  W=/tmp/s37/R_$ARM  # copies, not links: the run finder does not follow links
  if [ ! -d $W/runs/semantic ]; then
    rm -rf $W; mkdir -p $W/runs
    for b in geometric textural; do cp -r /tmp/w37/outputs/demo/runs/$b $W/runs/$b; done
    cp -r /tmp/s37/sem$ARM $W/runs/semantic
  fi
fi
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 SDN3D_CONFIG_DIR=$CODE/conf
cd $CODE && /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=$TREE 'data.image_size=[312,96]' run=$W \
  'compose=[photo]' "proposals=[$ROW]" scene=derender threads=1 examples=0 output_dir=$OUT > $OUT.log 2>&1
echo "$TREE $ARM $ROW rc=$? $(date -u +%T)"
