#!/usr/bin/env bash
# diag.sh TREE SEED (MODES="loc shape": those oracle rows alone): on TREE, the predicted row with ground-truth geometry (ORACLE=geo) and with the ground-truth yaw
# alone (ORACLE=yaw) swapped into the fitted proposals (oracle_pose.py), and the ground-truth-mask row (an oracle);
# w37, main at this session's start (/tmp/s37_base), 312x96, one thread. Outputs /tmp/s37/t1/SEED_{geo,yaw,gt}.
set -u
TREE=$1; SEED=$2; CODE=/tmp/s37_base; W=/tmp/w37/outputs/demo; O=/tmp/s37/t1
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 SDN3D_CONFIG_DIR=$CODE/conf
ARGS=("data.root=$TREE" 'data.image_size=[312,96]' "run=$W" 'compose=[photo]' scene=derender threads=1 examples=0)
for M in ${MODES:-geo yaw}; do
  (cd $CODE && ORACLE=$M /work/main/.venv/bin/python /work/main/docs/results/2026-12-02_cpu/session37/lead/posediag/scripts/oracle_pose.py \
     "${ARGS[@]}" 'proposals=[semantic]' output_dir=$O/${SEED}_$M > $O/${SEED}_$M.log 2>&1)
  echo "$TREE $M rc=$? $(date -u +%T)"
done
[ -n "${MODES:-}" ] && exit 0
(cd $CODE && /work/main/.venv/bin/python -m sdn3d.cli.bench "${ARGS[@]}" 'proposals=[gt]' output_dir=$O/${SEED}_gt > $O/${SEED}_gt.log 2>&1)
echo "$TREE gt rc=$? $(date -u +%T)"
