#!/bin/bash
# gtlane.sh CODE TAG SEED SOURCE...: derender rows (given sources) on tree SEED with a cache per code tag and seed
code=$1; tag=$2; seed=$3; shift 3
case $seed in 31) t=/tmp/s4data/lead/t1_31;; 35) t=/tmp/s6data/lead/t1_35;; 37) t=/tmp/s7data/haze/t1_37;; 39) t=/tmp/s7data/haze/t1_39;; 2097) t=/tmp/s10data/semflip/t1_2097;; 2107) t=/tmp/s10data/semflip/t1_2107;; esac
cd /tmp/s10data/semflip
for p in "$@"; do ./run.sh $code ${tag}${seed}_$p $t $p derender /tmp/s10data/semflip/cache_${tag}_$seed 0; done
