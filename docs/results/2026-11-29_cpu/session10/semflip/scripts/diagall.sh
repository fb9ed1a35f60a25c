#!/bin/bash
# diagall.sh NAME SEED CODE TAG: diag.py for one run (flips per weather of the rotate entries' cars)
n=$1; s=$2; code=$3; tag=$4
case $s in 31) t=/tmp/s4data/lead/t1_31;; 35) t=/tmp/s6data/lead/t1_35;; 37) t=/tmp/s7data/haze/t1_37;; 39) t=/tmp/s7data/haze/t1_39;; 2097) t=/tmp/s10data/semflip/t1_2097;; 2107) t=/tmp/s10data/semflip/t1_2107;; esac
cd $code && PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s10data/semflip/diag.py $t /tmp/s10data/semflip/runs/$n /tmp/s10data/semflip/cache_${tag}_$s > /tmp/s10data/semflip/runs/$n.diag.txt 2>&1
