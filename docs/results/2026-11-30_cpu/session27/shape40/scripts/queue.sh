#!/bin/bash
# queue.sh CODE NAME: this helper's tuning queue for one code tree (one lane; main's and the branch's lanes run side by
# side, two processes at most): counterfactual turns with predicted geometry on cf31/cf33/cf39 (cf.sh), Table 1 photo
# rows on t1_35/t1_37 (t1.sh), the real frame's strip (issue40_41/real_strip.py of CODE's tree, run w0).
HERE=$(cd $(dirname $0) && pwd); CODE=$1; NAME=$2; L=/tmp/s27data/shape40/queue_$NAME.log
bash $HERE/cf.sh $CODE $NAME /tmp/s21data/trees/cf31 /tmp/s21data/trees/cf33 /tmp/s21data/trees/cf39 >> $L 2>&1
bash $HERE/t1.sh $CODE $NAME /tmp/s21data/trees/t1_35 /tmp/s21data/trees/t1_37 >> $L 2>&1
(cd $CODE && PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  docs/results/2026-11-28_cpu/issue40_41/real_strip.py /tmp/s21data/demo/out /tmp/s27data/shape40/strip_$NAME) >> $L 2>&1
echo "queue $NAME done $(date -u +%T)" >> $L
