#!/bin/bash
# measure_e.sh: measure.sh for the fifth code state E (road_lab), after measure.sh's runs
W=/work/wt/s9-rot05; R=$W/docs/results/2026-11-29_cpu/session9/rot05; D=/tmp/s9data/rot05; C=/tmp/s8data/photocost/t1cap
while ! grep -q "all done" $D/measure.log; do sleep 10; done
rm -rf $D/code_E; mkdir -p $D/code_E; (cd $W && git archive 696a290 src conf | tar -x -C $D/code_E)
( cd $D && PYTHONPATH=$D/code_E/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python $R/replay_photo.py rep_E --lat /tmp/s5data/deletes/lat3 --cap $C/gt_derender $C/semantic_derender $C/gt_oracle > rep_E.log 2>&1
  /work/main/.venv/bin/python $R/replay_photo.py --compare rep_main rep_E > $D/cmp_main_E.txt 2>&1
  /work/main/.venv/bin/python $R/replay_photo.py --compare rep_D rep_E > $D/cmp_D_E.txt 2>&1; echo "replay E done" ) > $D/lane3.log 2>&1 &
( bash $R/cf.sh $D/code_E $D/cf31_E; bash $R/t1.sh $D/code_E $D/t1_E ) > $D/lane4.log 2>&1 &
wait
echo "E done"
