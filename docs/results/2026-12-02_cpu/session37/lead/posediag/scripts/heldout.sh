#!/usr/bin/env bash
# heldout.sh SEED [ROWS...]: generate held-out moves tree SEED once (session 33's gen.py; refuses if it exists unless
# ROWS are given, which then run on the existing tree), then its rows (default: w37 geo gtfit gt): w37 = the predicted
# row (rows.sh), geo / gtfit = the predicted row with an oracle's geometry (oracle_pose.py), gt = the ground-truth-mask
# row (an oracle). Outputs /tmp/s37/held/SEED_<row>; log /tmp/s37/held/run.log.
set -u
SEED=$1; shift; ROWS=${*:-w37 geo gtfit gt}; H=/tmp/s37/held; TREE=$H/trees/t1d_$SEED; CODE=/tmp/s37_base
S=/work/main/docs/results/2026-12-02_cpu; PY=/work/main/.venv/bin/python; mkdir -p $H/trees
if [ $# -eq 0 ]; then
  [ -e "$TREE" ] && { echo "tree $TREE exists: one generation only" >&2; exit 3; }
  (cd $CODE && PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 $PY $S/session33/lead/deletes/scripts/gen.py $TREE $SEED moves \
     > $H/gen_$SEED.log 2>&1); echo "$SEED gen rc=$? $(date -u +%T)" >> $H/run.log
fi
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 SDN3D_CONFIG_DIR=$CODE/conf
ARGS=("data.root=$TREE" 'data.image_size=[312,96]' run=/tmp/w37/outputs/demo 'compose=[photo]' scene=derender threads=1 examples=0)
for R in $ROWS; do
  case $R in
    w37) (cd $CODE && $PY -m sdn3d.cli.bench "${ARGS[@]}" 'proposals=[semantic]' output_dir=$H/${SEED}_$R > $H/${SEED}_$R.log 2>&1) ;;
    gt) (cd $CODE && $PY -m sdn3d.cli.bench "${ARGS[@]}" 'proposals=[gt]' output_dir=$H/${SEED}_$R > $H/${SEED}_$R.log 2>&1) ;;
    *) (cd $CODE && ORACLE=$R $PY $S/session37/lead/posediag/scripts/oracle_pose.py "${ARGS[@]}" 'proposals=[semantic]' \
          output_dir=$H/${SEED}_$R > $H/${SEED}_$R.log 2>&1) ;;
  esac
  echo "$SEED $R rc=$? $(date -u +%T)" >> $H/run.log
done
