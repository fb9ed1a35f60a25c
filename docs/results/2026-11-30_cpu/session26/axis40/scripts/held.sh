#!/bin/bash
# held.sh gen|pose|t1|tables: the held-out run on seed 2255 (README's merge rule), once. MAIN and BRANCH: plain trees
# of main (9fa5234) and of this branch's final commit (git archive). Outputs under /tmp/s26data/axis40/held.
#   gen:    the Table 1 tree (main's generator, gen_t1.py OUT 2255)
#   pose:   diag.sh of both codes, rows gt_fit and pred_fit (two processes)
#   t1:     Table 1 photo rows of both codes, each with its own de-render cache (two processes)
#   tables: the paired tables into ../tables/heldout2255_*
HERE=$(cd $(dirname $0) && pwd); PY=/work/main/.venv/bin/python; H=/tmp/s26data/axis40/held; mkdir -p $H
MAIN=${MAIN:-/tmp/s26data/lead/base_9fa}; BRANCH=${BRANCH:?plain tree of the branch}; TREE=$H/trees/t1_2255
case $1 in
  gen) cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 $PY $HERE/gen_t1.py $TREE 2255 > $H/gen.log 2>&1 ;;
  pose) bash $HERE/diag.sh $MAIN $TREE $H/main_2255 gt_fit pred_fit > $H/pose_main.log 2>&1 &
        bash $HERE/diag.sh $BRANCH $TREE $H/br_2255 gt_fit pred_fit > $H/pose_br.log 2>&1; wait ;;
  t1) T1OUT=$H/t1 TREES=$H/trees CACHE_TAG=main bash $HERE/t1.sh $MAIN main 2255 &
      T1OUT=$H/t1 TREES=$H/trees CACHE_TAG=br bash $HERE/t1.sh $BRANCH br 2255; wait ;;
  tables) T=$HERE/../tables
    for r in gt_fit pred_fit; do $PY $HERE/pose_paired.py $r $H/main_2255.json:$H/br_2255.json > $T/heldout2255_pose_$r.txt; done
    python3 $HERE/axis.py $H/main_2255 > $T/heldout2255_axis_main.txt
    python3 $HERE/axis.py $H/br_2255 > $T/heldout2255_axis_branch.txt
    for p in semantic gt; do $PY $HERE/compare.py "held-out 2255, $p" $H/t1/main2255_$p:$H/t1/br2255_$p > $T/heldout2255_table1_$p.txt; done ;;
esac
