#!/bin/bash
# measure.sh: per code state (main fc689d8, then this branch's commits A..D taken in turn), the replays of lat3 and of
# session 8's captured Table 1 calls, the counterfactual bench on cf31 and Table 1 (oracle) on t1_31; two lanes
W=/work/wt/s9-rot05; R=$W/docs/results/2026-11-29_cpu/session9/rot05; D=/tmp/s9data/rot05; C=/tmp/s8data/photocost/t1cap
declare -A REV=([B]=ed1958c [C]=818cba1 [D]=2c43fd0)
for x in B C D; do rm -rf $D/code_$x; mkdir -p $D/code_$x; (cd $W && git archive ${REV[$x]} src conf | tar -x -C $D/code_$x); done
cp -r $D/main_code $D/code_main 2>/dev/null
replay() {  # replay X PREV
  cd $D && PYTHONPATH=$D/code_$1/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python $R/replay_photo.py rep_$1 --lat /tmp/s5data/deletes/lat3 --cap $C/gt_derender $C/semantic_derender $C/gt_oracle > rep_$1.log 2>&1
  /work/main/.venv/bin/python $R/replay_photo.py --compare rep_main rep_$1 > $D/cmp_main_$1.txt 2>&1
  /work/main/.venv/bin/python $R/replay_photo.py --compare rep_$2 rep_$1 > $D/cmp_$2_$1.txt 2>&1
  echo "replay $1 done"
}
( replay B A; replay C B; replay D C; bash $R/t1.sh $D/code_D $D/t1_D ) > $D/lane1.log 2>&1 &
( bash $R/t1.sh $D/main_code $D/t1_main; for x in B C D; do bash $R/cf.sh $D/code_$x $D/cf31_$x; done; bash $R/t1.sh $D/code_B $D/t1_B; bash $R/t1.sh $D/code_C $D/t1_C ) > $D/lane2.log 2>&1 &
wait
echo all done
