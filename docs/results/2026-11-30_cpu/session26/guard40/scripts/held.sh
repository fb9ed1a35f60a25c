#!/bin/bash
# held.sh gen|pose|t1|tables: the held-out run on seed 2257 (README's merge rule), once (session 26 guard40; axis40's
# held.sh with its seed and paths). MAIN and BRANCH: plain trees of main (9fa5234, /tmp/s26data/lead/base_9fa) and of
# this branch's final library commit (git archive). Outputs under /tmp/s26data/guard40/held.
#   gen:    the Table 1 tree (main's generator, gen_t1.py OUT 2257)
#   pose:   diag.sh of both codes, rows gt_fit and pred_fit (two processes)
#   t1:     Table 1 photo rows of both codes, each with its own de-render cache (two processes)
#   tables: the paired tables into ../tables/heldout2257_*
HERE=$(cd $(dirname $0) && pwd); PY=/work/main/.venv/bin/python; H=/tmp/s26data/guard40/held; mkdir -p $H
MAIN=${MAIN:-/tmp/s26data/lead/base_9fa}; BRANCH=${BRANCH:?plain tree of the branch}; TREE=$H/trees/t1_2257
case $1 in
  gen) cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 $PY $HERE/gen_t1.py $TREE 2257 > $H/gen.log 2>&1 ;;
  pose) bash $HERE/diag.sh $MAIN $TREE $H/main_2257 gt_fit pred_fit > $H/pose_main.log 2>&1 &
        bash $HERE/diag.sh $BRANCH $TREE $H/br_2257 gt_fit pred_fit > $H/pose_br.log 2>&1; wait ;;
  t1) T1OUT=$H/t1 TREES=$H/trees CACHE_TAG=main bash $HERE/t1.sh $MAIN main 2257 &
      T1OUT=$H/t1 TREES=$H/trees CACHE_TAG=br bash $HERE/t1.sh $BRANCH br 2257; wait ;;
  tables) T=$HERE/../tables
    for r in gt_fit pred_fit; do
      $PY $HERE/pose_paired.py $r $H/main_2257.json:$H/br_2257.json > $T/heldout2257_pose_$r.txt
      $PY $HERE/axis_paired.py $r $H/main_2257.json:$H/br_2257.json > $T/heldout2257_axis_$r.txt
    done
    python3 $HERE/axis.py $H/main_2257 > $T/heldout2257_axis_main.txt
    python3 $HERE/axis.py $H/br_2257 > $T/heldout2257_axis_branch.txt
    for p in semantic gt; do
      $PY $HERE/compare.py "held-out 2257, $p" $H/t1/main2257_$p:$H/t1/br2257_$p > $T/heldout2257_table1_$p.txt
    done ;;
esac
