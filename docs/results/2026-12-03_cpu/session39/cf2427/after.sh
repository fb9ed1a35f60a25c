#!/bin/bash
# Session 39 cf2427: what ran after run.sh (its four benchmark runs): the tables, the cut JSONs and the pictures.
S=/tmp/s39cf; R=/tmp/w39/outputs/demo/runs; D=$(cd "$(dirname "$0")" && pwd); PY=/work/main/.venv/bin/python
export OMP_NUM_THREADS=1
# tables (from the full JSONs; the cut ones in this folder give the same up to the 4th decimal of one L1 cell)
PYTHONPATH=$S/main_code/src:$S/main_code $PY $D/analyze.py $S/issue_oracle/counterfactual.json \
  $S/main_oracle/counterfactual.json $S/issue_pred/counterfactual.json $S/main_pred/counterfactual.json > $D/tables.md
for r in issue_oracle main_oracle issue_pred main_pred; do
  cp $S/$r/counterfactual.md $D/${r}_counterfactual.md; python3 $D/slim.py $S/$r/counterfactual.json $D/${r}_pairs.json.gz
done
# pictures: 4 targets fixed before any result was read (the first clone target of worlds 0001, 0006, 0018, 0009)
$PY $D/pics.py subtree $S/t2427 $S/pics_sub 0001/clone/00026_12002 0006/clone/00024_12007 0018/clone/00025_12004 0009/clone/00024_12006
(cd $S/issue_time && PYTHONPATH=$PWD/src:$PWD nice -n 5 $PY $D/pics.py draw $S/pics_sub $S/pics_issue photo:auto run=$R \
  threads=1 'counterfactual_sources=[oracle]')
(cd $S/main_code && PYTHONPATH=$PWD/src:$PWD nice -n 5 $PY $D/pics.py draw $S/pics_sub $S/pics_main photo:rays run=$R \
  threads=1 'counterfactual_sources=[oracle]' 'counterfactual_fills=[auto,telea,patchmatch,rays,learnt]' 'counterfactual_kinds=[turn,delete]')
$PY $D/pics.py sheet $S/pics_sub $D/pairs_sheet.png issue-time=$S/pics_issue main=$S/pics_main
