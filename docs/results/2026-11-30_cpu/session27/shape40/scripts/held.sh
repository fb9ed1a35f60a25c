#!/bin/bash
# held.sh: the held-out measurement (seed 2265), once, after the merge rule was committed: generate the Table 1 tree
# with main's generator (gen_t1.py, session 9 fogflip's recipe), then the pose table (gt_fit, pred_fit) and Table 1
# rows (semantic, gt) of main (9bee856) and of the branch (git archive of 9b5672a), side by side (two processes).
HERE=$(cd $(dirname $0) && pwd); MAIN=/tmp/s27data/lead/base_9be; BR=/tmp/s27data/shape40/code_9b5
TREE=/tmp/s27data/shape40/trees/t1_2265; H=/tmp/s27data/shape40/held; mkdir -p $H /tmp/s27data/shape40/trees
(cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE 2265) > $H/gen.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $H/held.log
bash $HERE/pose.sh $MAIN $TREE $H/pose_main.json gt_branch gt_fit pred_fit > $H/pose_main.log 2>&1 &
bash $HERE/pose.sh $BR $TREE $H/pose_br.json gt_fit pred_fit > $H/pose_br.log 2>&1
wait
echo "pose done $(date -u +%T)" >> $H/held.log
bash $HERE/t1.sh $MAIN main $TREE &
bash $HERE/t1.sh $BR br $TREE
wait
echo "t1 done $(date -u +%T)" >> $H/held.log
