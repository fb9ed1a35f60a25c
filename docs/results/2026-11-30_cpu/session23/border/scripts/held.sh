#!/bin/bash
# held.sh BRANCH_CODE: held-out 2213 (issue 40, session 23 border), run once after the library was final.
# Slot A: the tree (gen_t1.py with main's code), then main's pose table and Table 1 rows; slot B (after the tree):
# the branch's. Pose tables: diag.sh (pose_table.py --part all, 40 frames; rows gt_branch gt_fit pred_fit); Table 1:
# t1.sh (semantic proposals, then ground-truth masks (oracle)). Weights w0. Two processes at most: env WAIT_LINE, a
# line that slot B waits for in /tmp/s23data/border/t1/t1.log before it starts (another run holding the second slot).
HERE=$(cd $(dirname $0) && pwd); BR=$1; MAIN=/tmp/s23data/lead/base_73c; H=/tmp/s23data/border/held
TREE=$H/t1_2213; mkdir -p $H; LOG=$H/held.log
echo "start $(date -u +%T)" >> $LOG
(cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
   /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE 2213 > $H/gen2213.log 2>&1)
echo "tree rc=$? $(date -u +%T)" >> $LOG
(bash $HERE/diag.sh $MAIN $TREE $H/pose_main > $H/pose_main.log 2>&1; echo "pose main rc=$? $(date -u +%T)" >> $LOG
 TREES=$H bash $HERE/t1.sh $MAIN main 2213; echo "t1 main done $(date -u +%T)" >> $LOG) &
(while [ -n "$WAIT_LINE" ] && ! grep -q "$WAIT_LINE" /tmp/s23data/border/t1/t1.log 2>/dev/null; do sleep 10; done
 bash $HERE/diag.sh $BR $TREE $H/pose_branch > $H/pose_branch.log 2>&1; echo "pose branch rc=$? $(date -u +%T)" >> $LOG
 TREES=$H bash $HERE/t1.sh $BR branch 2213; echo "t1 branch done $(date -u +%T)" >> $LOG) &
wait
echo "all $(date -u +%T)" >> $LOG
