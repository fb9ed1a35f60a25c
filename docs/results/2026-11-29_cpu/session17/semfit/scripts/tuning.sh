#!/bin/bash
# tuning.sh CODE TAG [ROWS]: one code on tuning Table 1 trees 35, 37, 31 (ROWS default "semantic gt"), its own caches.
S=$(dirname "$0"); code=$1; tag=$2; rows=${3:-semantic gt}
for seed in 35 37 31; do
  case $seed in 31) T=/tmp/s11data/lead/t1_31;; *) T=/tmp/s11data/semrain/t1_$seed;; esac
  for p in $rows; do "$S/run.sh" "$code" "$tag$seed"_$p $T $p /tmp/s17data/semfit/cache_$tag$seed; done
done
echo "$tag tuning done $(date +%T)"
