#!/bin/bash
# lane.sh CODE TAG SEED: gt and semantic derender rows on tree SEED with a cache per code tag and seed
code=$1; tag=$2; seed=$3
case $seed in 31) t=/tmp/s4data/lead/t1_31;; 35) t=/tmp/s6data/lead/t1_35;; 37) t=/tmp/s7data/haze/t1_37;; 39) t=/tmp/s7data/haze/t1_39;; 2097) t=/tmp/s9data/fogflip/t1_2097;; esac
cd /tmp/s9data/fogflip
for p in gt semantic; do ./run.sh $code ${tag}${seed}_$p $t $p derender /tmp/s9data/fogflip/cache_${tag}_$seed 0; done
