#!/bin/bash
# held.sh: held-out seed 2165, generated once the code was final and measured once: the Table 1 tree (session 9
# fogflip's gen_t1.py), Table 1 photo rows of main (/tmp/s18data/lead/base_5df) and of the branch's final code
# (/tmp/s18data/tierule/code_final) on semantic proposals and ground-truth masks (oracle), then the proposal fits'
# captures and replays (the fit's template accuracy beside the majority floor, flips, yaw error).
HERE=$(cd $(dirname $0) && pwd); SEED=2165; TREE=/tmp/s18data/tierule/t1_$SEED; CODE=/work/wt/tierule
LOG=/tmp/s18data/tierule/held.log
[ -e $TREE/_SUCCESS ] || (cd /tmp/s18data/lead/base_5df && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 nice -n 5 \
  /work/main/.venv/bin/python /work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $TREE $SEED \
  > /tmp/s18data/tierule/gen_$SEED.log 2>&1)
echo "gen rc=$? $(date -u +%T)" >> $LOG
bash $HERE/t1.sh /tmp/s18data/lead/base_5df main "semantic gt" $SEED
bash $HERE/t1.sh /tmp/s18data/tierule/code_final final "semantic gt" $SEED
echo "t1 done $(date -u +%T)" >> $LOG
for P in semantic gt; do
  (cd $CODE && PYTHONPATH=$CODE/src:$CODE OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $HERE/capture.py \
     $TREE /tmp/s18data/tierule/t1/cache_main$SEED /tmp/s18data/tierule/cap/${P}$SEED $P > /tmp/s18data/tierule/cap/${P}$SEED.log 2>&1)
done
echo "capture done $(date -u +%T)" >> $LOG
TAG= bash $HERE/replay_all.sh base,0.03 $SEED
echo "replay done $(date -u +%T)" >> $LOG
