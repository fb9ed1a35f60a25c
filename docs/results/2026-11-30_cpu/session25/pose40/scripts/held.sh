#!/bin/bash
# held.sh STEP: held-out 2235 (README's merge rule), main 9a61b5b (/tmp/s25data/lead/base_9a6) against this worktree,
# weights w0, outputs under /tmp/s25data/pose40/held/. Run from anywhere, one step at a time (two processes each):
#   held.sh gen    the Table 1 tree (main's generator, gen_t1.py OUT 2235)
#   held.sh pose   diag.sh (pose table rows gt_fit and pred_fit, with the fit's decisions) of both codes
#   held.sh t1     Table 1 rows (semantic, then gt) of both codes, each with its own de-render cache
HERE=$(cd $(dirname $0) && pwd); PY=/work/main/.venv/bin/python
MAIN=/tmp/s25data/lead/base_9a6; BR=/work/wt/pose40; H=/tmp/s25data/pose40/held; mkdir -p $H/trees
case $1 in
  gen) (cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 $PY $HERE/gen_t1.py $H/trees/t1_2235 2235);;
  pose) bash $HERE/diag.sh $MAIN $H/trees/t1_2235 $H/main_2235 gt_fit pred_fit > $H/main_pose.log 2>&1 &
        bash $HERE/diag.sh $BR $H/trees/t1_2235 $H/br_2235 gt_fit pred_fit > $H/br_pose.log 2>&1; wait;;
  t1) for P in semantic gt; do
        TREES=$H/trees T1OUT=$H/t1 CACHE_TAG=main ROWS=$P bash $HERE/t1.sh $MAIN main 2235 &
        TREES=$H/trees T1OUT=$H/t1 CACHE_TAG=br ROWS=$P bash $HERE/t1.sh $BR br 2235; wait
      done;;
  *) echo "usage: held.sh gen|pose|t1"; exit 2;;
esac
