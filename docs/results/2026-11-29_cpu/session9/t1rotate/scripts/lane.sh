#!/bin/bash
# lane.sh CODE TAG SEED AIR_MIN: gt and semantic derender rows on tree SEED (31 or 35) with the base cache
code=$1; tag=$2; seed=$3; m=$4
case $seed in 31) t=/tmp/s4data/lead/t1_31;; 35) t=/tmp/s6data/lead/t1_35;; 37) t=/tmp/s7data/haze/t1_37;; 39) t=/tmp/s7data/haze/t1_39;; esac
cd /tmp/s9data/t1rotate
for p in gt semantic; do AIR_MIN=$m ./run.sh $code ${tag}${seed}_$p $t $p derender /tmp/s9data/t1rotate/cache_${CACHE:-base}_$seed 0; done
