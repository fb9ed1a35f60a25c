#!/bin/bash
# run.sh SEED: generate the held-out moves tree SEED once (session 33's gen.py, kind moves; refuses if it exists), then
# both Table 1 photo rows (semantic = predicted, gt = ground-truth masks, an oracle) at 312x96 with weights w36, and
# the floor (session 30's floor.py). CODE: a plain worktree of main 5d254108. Outputs under $B/out.
set -u
SEED=$1; B=${B:-/tmp/s36/t1held}; CODE=/tmp/s36_lead_base; W=/tmp/w36/outputs/demo; TREE=$B/trees/t1d_$SEED
PY=/work/main/.venv/bin/python; S=/work/main/docs/results; mkdir -p $B/trees $B/out
[ -e "$TREE" ] && { echo "tree $TREE exists: one generation only" >&2; exit 3; }
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 SDN3D_CONFIG_DIR=$CODE/conf
echo "$SEED gen start $(date -u +%T)" >> $B/run.log
(cd $CODE && $PY $S/2026-12-02_cpu/session33/lead/deletes/scripts/gen.py $TREE $SEED moves > $B/out/gen_$SEED.log 2>&1); echo "$SEED gen rc=$? $(date -u +%T)" >> $B/run.log
for ROW in semantic gt; do
  (cd $CODE && $PY -m sdn3d.cli.bench data.root=$TREE 'data.image_size=[312,96]' run=$W 'compose=[photo]' "proposals=[$ROW]" \
     scene=derender threads=1 examples=0 output_dir=$B/out/${SEED}_$ROW > $B/out/${SEED}_$ROW.log 2>&1)
  echo "$SEED $ROW rc=$? $(date -u +%T)" >> $B/run.log
done
(cd $CODE && $PY $S/2026-12-01_cpu/session30/t1big30/scripts/floor.py $TREE $B/out/floor_$SEED.json > $B/out/floor_$SEED.log 2>&1); echo "$SEED floor rc=$? $(date -u +%T)" >> $B/run.log
