#!/bin/bash
# branch_tuning.sh CODE TAG: a git archive of the branch (CODE) on tuning Table 1 trees 35, 37, 31, both rows, after
# main_tuning.sh's queue (one heavy process at a time).
S=$(dirname "$0"); B=$1; tag=$2; C=/tmp/s16data/picks
while pgrep -f main_tuning.sh > /dev/null; do sleep 20; done
for seed in 35 37 31; do
  case $seed in 31) T=/tmp/s11data/lead/t1_31;; *) T=/tmp/s11data/semrain/t1_$seed;; esac
  for p in ${ROWS:-semantic gt}; do $S/run.sh $B ${tag}${seed}_$p $T $p $C/cache_${tag}$seed; done
done
echo $tag tuning done
