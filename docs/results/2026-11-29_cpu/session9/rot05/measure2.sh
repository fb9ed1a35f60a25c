#!/bin/bash
# measure2.sh: the rest of measure.sh and measure_e.sh in two lanes (D was bit-identical to C on all 344 replayed calls:
# its Table 1 oracle run, the same calls, and its cf31 run were not repeated)
W=/work/wt/s9-rot05; R=$W/docs/results/2026-11-29_cpu/session9/rot05; D=/tmp/s9data/rot05; C=/tmp/s8data/photocost/t1cap
rm -rf $D/code_E; mkdir -p $D/code_E; (cd $W && git archive 696a290 src conf | tar -x -C $D/code_E)
( while [ ! -f $D/cf31_C/counterfactual.json ]; do sleep 5; done; sleep 5
  bash $R/t1.sh $D/code_B $D/t1_B; bash $R/t1.sh $D/code_C $D/t1_C ) > $D/lane5.log 2>&1 &
( cd $D && PYTHONPATH=$D/code_E/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python $R/replay_photo.py rep_E --lat /tmp/s5data/deletes/lat3 --cap $C/gt_derender $C/semantic_derender $C/gt_oracle > rep_E.log 2>&1
  /work/main/.venv/bin/python $R/replay_photo.py --compare rep_main rep_E > $D/cmp_main_E.txt 2>&1
  /work/main/.venv/bin/python $R/replay_photo.py --compare rep_D rep_E > $D/cmp_D_E.txt 2>&1; echo "replay E done"
  bash $R/cf.sh $D/code_E $D/cf31_E; bash $R/t1.sh $D/code_E $D/t1_E ) > $D/lane6.log 2>&1 &
wait
echo "all done"
