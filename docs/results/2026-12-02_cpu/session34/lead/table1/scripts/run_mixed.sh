#!/bin/bash
# run.sh SEED: held-out Table 1 tree SEED (gen_t1.py, session 9's recipe) generated once, then both photo rows
# (semantic = predicted, gt = ground-truth masks, oracle) at 312x96 with w34 (the final demo run) and main's code, and the
# floor (session 30's floor.py). Outputs under /tmp/s34/t1tab/out.
set -u
SEED=$1; B=/tmp/s34/t1tab; W=/tmp/s34/demo2/outputs/demo; TREE=$B/trees/t1_$SEED; PY=/work/main/.venv/bin/python
mkdir -p $B/trees $B/out; [ -e "$TREE" ] && { echo "tree exists" >&2; exit 3; }
export OMP_NUM_THREADS=1; cd /work/main
echo "$SEED gen start $(date -u +%T)" >> $B/run.log
$PY docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE $SEED > $B/out/gen_$SEED.log 2>&1; echo "$SEED gen rc=$? $(date -u +%T)" >> $B/run.log
for ROW in semantic gt; do
  ($PY -m sdn3d.cli.bench data.root=$TREE 'data.image_size=[312,96]' run=$W 'compose=[photo]' "proposals=[$ROW]" \
     scene=derender threads=1 examples=0 output_dir=$B/out/${SEED}_$ROW > $B/out/${SEED}_$ROW.log 2>&1; echo "$SEED $ROW rc=$? $(date -u +%T)" >> $B/run.log) &
done
$PY docs/results/2026-12-01_cpu/session30/t1big30/scripts/floor.py $TREE $B/out/floor_$SEED.json > $B/out/floor_$SEED.log 2>&1; echo "$SEED floor rc=$? $(date -u +%T)" >> $B/run.log
wait
