#!/bin/bash
# diagall.sh NAME SEED CODE TAG: diag.py for one run (flips per weather of the rotate entries' cars)
n=$1; s=$2; code=$3; tag=$4
case $s in 31) t=/tmp/s4data/lead/t1_31;; 35) t=/tmp/s6data/lead/t1_35;; 37) t=/tmp/s7data/haze/t1_37;; 39) t=/tmp/s7data/haze/t1_39;; 2097) t=/tmp/s9data/fogflip/t1_2097;; esac
cd $code && PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s9data/fogflip/diag.py $t /tmp/s9data/fogflip/runs/$n /tmp/s9data/fogflip/cache_${tag}_$s > /tmp/s9data/fogflip/runs/$n.diag.txt 2>&1
