#!/bin/bash
# queue.sh TREE_LABEL...: the turn benchmarks (rays fill) of main (/tmp/s21data/lead/base_1ac155c) and the branch (a
# git archive at /tmp/s21side/branch_src) on /tmp/s21data/trees/cf<LABEL> (or /tmp/s21side/trees/cf<LABEL>), oracle
# and predicted, two at a time (main and branch together). Out: /tmp/s21side/bench/{main,branch}_cf<LABEL>_<source>.
B=$(dirname "$0")/bench.sh
for t in "$@"; do
  tree=/tmp/s21data/trees/cf$t; [ -d "$tree" ] || tree=/tmp/s21side/trees/cf$t
  for s in oracle semantic; do
    bash "$B" /tmp/s21data/lead/base_1ac155c "$tree" "/tmp/s21side/bench/main_cf${t}_$s" "$s" "[rays]" "[turn]" &
    bash "$B" /tmp/s21side/branch_src "$tree" "/tmp/s21side/bench/branch_cf${t}_$s" "$s" "[rays]" "[turn]" &
    wait
  done
done
