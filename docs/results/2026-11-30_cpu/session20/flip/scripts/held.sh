#!/bin/bash
# held.sh STAGE: held-out seed 2175, generated once the code was final and measured once. BRANCH: the branch's final
# code (a git archive of it). STAGE "pose": the Table 1 tree (session 9 fogflip's gen_t1.py, main's code), then pose
# tables (session 11 template's pose.sh: benchmarks/pose_table.py --part all, 40 frames, 312x96, photo crops, threads
# 1, min-pixels 64, session 11's demo weights; rows gt_fit, pred_fit) of main (/tmp/s20data/lead/base_4044) and of the
# branch. STAGE "t1": Table 1 photo rows (t1.sh) of main and of the branch on semantic proposals and ground-truth masks
# (oracle). The two stages ran side by side (the session's deadline), each on one thread.
HERE=$(cd $(dirname $0) && pwd); SEED=2175; TREE=/tmp/s20data/flip/t1_$SEED; MAIN=/tmp/s20data/lead/base_4044
BRANCH=${BRANCH:?}; OUT=/tmp/s20data/flip/held; LOG=$OUT/held.log; mkdir -p $OUT
POSE=/work/main/docs/results/2026-11-29_cpu/session11/template/scripts/pose.sh
case $1 in
  pose)
    [ -e $TREE/_SUCCESS ] || (cd $MAIN && PYTHONPATH=$MAIN/src:$MAIN OMP_NUM_THREADS=1 nice -n 5 \
      /work/main/.venv/bin/python /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE $SEED \
      > $OUT/gen.log 2>&1)
    echo "gen rc=$? $(date -u +%T)" >> $LOG
    for C in main:$MAIN branch:$BRANCH; do
      BENCH=${C#*:}/benchmarks/pose_table.py bash $POSE ${C#*:} $TREE $OUT/pose_${C%%:*}.json gt_fit pred_fit \
        > $OUT/pose_${C%%:*}.log 2>&1
      echo "pose ${C%%:*} rc=$? $(date -u +%T)" >> $LOG
    done;;
  t1)
    bash $HERE/t1.sh $MAIN main $SEED
    bash $HERE/t1.sh $BRANCH flip $SEED
    echo "t1 done $(date -u +%T)" >> $LOG;;
esac
