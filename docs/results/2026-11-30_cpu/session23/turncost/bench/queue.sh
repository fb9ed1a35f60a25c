#!/bin/bash
# queue.sh OUT: the counterfactual benches of session 23 turncost, one after another (fill rays, turn and delete
# pairs, threads 1, nice 5; bench.sh is session 21 speck's): main 73c0792 (/tmp/s23data/lead/base_73c) and the branch
# (/tmp/s23data/turncost/code_kd, a git archive of 3bb359b) on the tuning trees cf31 (predicted; its oracle runs are
# session 22's identity outputs.sh's) and cf33 (oracle and predicted), then, once the held-out tree is generated
# (gen_cf.py printed "done" into /tmp/s23data/turncost/gen2217.log), on held-out 2217 (oracle and predicted).
set -u
O=$1; mkdir -p $O; D=$(cd "$(dirname "$0")" && pwd)
MAIN=/tmp/s23data/lead/base_73c; KD=/tmp/s23data/turncost/code_kd
run() {  # TREE_NAME TREE SOURCE
  for c in main:$MAIN kd:$KD; do
    echo "${c%%:*} $1 $3 start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/queue.log
    bash $D/bench.sh ${c#*:} $2 $O/${c%%:*}_$1_$3 $3 '[rays]' '[turn,delete]' >> $O/queue.log
  done
}
run cf31 /tmp/s21data/trees/cf31 semantic
run cf33 /tmp/s21data/trees/cf33 oracle
run cf33 /tmp/s21data/trees/cf33 semantic
until grep -q "^done" /tmp/s23data/turncost/gen2217.log; do sleep 20; done
run cf2217 /tmp/s23data/turncost/cf2217 oracle
run cf2217 /tmp/s23data/turncost/cf2217 semantic
echo "DONE $(date -u +%T)" >> $O/queue.log
