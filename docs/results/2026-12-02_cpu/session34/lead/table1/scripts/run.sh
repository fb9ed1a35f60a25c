#!/bin/bash
# run.sh SEED KIND: generate the held-out tree SEED of KIND (gen.py: deletes or occluders) once (refuses if it exists), then both Table 1 photo rows
# (semantic = predicted, gt = ground-truth masks (oracle)) at 312x96 with weights w34 (session 34 final demo run), and the floor (floor.py).
# CODE: a plain tree of main (git archive), W: the demo run's outputs/demo. Outputs under /tmp/s33/deletes/.
set -u
# gen.py: session 33's, docs/results/2026-12-02_cpu/session33/lead/deletes/scripts/gen.py (the session ran a copy beside this script)
SEED=$1; KIND=$2; B=${B:-/tmp/s34/moves}; CODE=$B/base; W=/tmp/s34/demo2/outputs/demo; TREE=$B/trees/t1d_$SEED
HERE=$(cd "$(dirname "$0")" && pwd); PY=/work/main/.venv/bin/python; mkdir -p $B/trees $B/out
[ -e "$TREE" ] && { echo "tree $TREE exists: one generation only" >&2; exit 3; }
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1
echo "$SEED gen start $(date -u +%T)" >> $B/run.log
(cd $CODE && nice -n 5 $PY $HERE/gen.py $TREE $SEED $KIND > $B/out/gen_$SEED.log 2>&1); echo "$SEED gen rc=$? $(date -u +%T)" >> $B/run.log
for ROW in semantic gt; do
  (cd $CODE && SDN3D_CONFIG_DIR=$CODE/conf nice -n 5 $PY -m sdn3d.cli.bench data.root=$TREE 'data.image_size=[312,96]' \
     run=$W 'compose=[photo]' "proposals=[$ROW]" scene=derender threads=1 examples=0 \
     output_dir=$B/out/${SEED}_$ROW > $B/out/${SEED}_$ROW.log 2>&1)
  echo "$SEED $ROW rc=$? $(date -u +%T)" >> $B/run.log
done
(cd $CODE && nice -n 5 $PY /work/main/docs/results/2026-12-01_cpu/session30/t1big30/scripts/floor.py $TREE $B/out/floor_$SEED.json > $B/out/floor_$SEED.log 2>&1); echo "$SEED floor rc=$? $(date -u +%T)" >> $B/run.log
