#!/bin/bash
# held.sh BRANCH_CODE: held-out 2203 (issue 40, session 22 flip), run once after the library was final.
# Slot A: the tree (gen_t1.py with main's code), then main's pose table and Table 1 rows; slot B (after the tree):
# the branch's. Pose tables: diag.sh (pose_table.py --part all, 40 frames; rows gt_branch gt_fit pred_fit); Table 1:
# t1.sh (semantic proposals, then ground-truth masks (oracle)). Weights w0. Two processes at most: env WAIT_LINE, a
# line that slot B waits for in /tmp/s22data/flip/t1/t1.log before it starts (another run holding the second slot).
HERE=$(cd $(dirname $0) && pwd); BR=$1; MAIN=/tmp/s22data/lead/base_1e2; H=/tmp/s22data/flip/held
TREE=$H/t1_2203; mkdir -p $H; LOG=$H/held.log
echo "start $(date -u +%T)" >> $LOG
(cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
   /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE 2203 > $H/gen2203.log 2>&1)
echo "tree rc=$? $(date -u +%T)" >> $LOG
(bash $HERE/diag.sh $MAIN $TREE $H/pose_main > $H/pose_main.log 2>&1; echo "pose main rc=$? $(date -u +%T)" >> $LOG
 TREES=$H bash $HERE/t1.sh $MAIN main 2203; echo "t1 main done $(date -u +%T)" >> $LOG) &
(while [ -n "$WAIT_LINE" ] && ! grep -q "$WAIT_LINE" /tmp/s22data/flip/t1/t1.log 2>/dev/null; do sleep 10; done
 bash $HERE/diag.sh $BR $TREE $H/pose_branch > $H/pose_branch.log 2>&1; echo "pose branch rc=$? $(date -u +%T)" >> $LOG
 TREES=$H bash $HERE/t1.sh $BR branch 2203; echo "t1 branch done $(date -u +%T)" >> $LOG) &
wait
echo "all $(date -u +%T)" >> $LOG
