#!/bin/bash
# main_tuning.sh: main (9f19738, /tmp/s16data/lead/base_9f1) on tuning Table 1 trees 35, 37, 31, both rows.
S=$(dirname "$0"); B=/tmp/s16data/lead/base_9f1; C=/tmp/s16data/picks
for seed in 35 37 31; do
  case $seed in 31) T=/tmp/s11data/lead/t1_31;; *) T=/tmp/s11data/semrain/t1_$seed;; esac
  for p in semantic gt; do $S/run.sh $B m${seed}_$p $T $p $C/cache_main$seed; done
done
echo main tuning done
