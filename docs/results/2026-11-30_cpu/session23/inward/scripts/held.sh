#!/bin/bash
# held.sh BRANCH_CODE: held-out 2225 (issue 40, session 23 inward), run once after the library was final.
# The tree (gen_t1.py with main's code), then both codes' pose tables at once (diag.sh: pose_table.py --part all,
# 40 frames; rows gt_branch gt_fit pred_fit), then both codes' Table 1 rows at once (t1.sh: semantic proposals, then
# ground-truth masks (oracle)). Main: /tmp/s23data/lead/base_a9c. Weights w0. Two processes at most.
HERE=$(cd $(dirname $0) && pwd); BR=$1; MAIN=/tmp/s23data/lead/base_a9c; H=/tmp/s23data/inward/held
TREE=$H/t1_2225; mkdir -p $H; LOG=$H/held.log
echo "start $(date -u +%T)" >> $LOG
(cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
   /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE 2225 > $H/gen2225.log 2>&1)
echo "tree rc=$? $(date -u +%T)" >> $LOG
(bash $HERE/diag.sh $MAIN $TREE $H/pose_main > $H/pose_main.log 2>&1; echo "pose main rc=$? $(date -u +%T)" >> $LOG
 TREES=$H bash $HERE/t1.sh $MAIN main 2225; echo "t1 main done $(date -u +%T)" >> $LOG) &
(bash $HERE/diag.sh $BR $TREE $H/pose_branch > $H/pose_branch.log 2>&1; echo "pose branch rc=$? $(date -u +%T)" >> $LOG
 TREES=$H bash $HERE/t1.sh $BR branch 2225; echo "t1 branch done $(date -u +%T)" >> $LOG) &
wait
echo "all $(date -u +%T)" >> $LOG
