#!/bin/bash
# capall.sh CODE TAG: capfit.py (semantic and gt) on every variation of the rotate entries of tuning trees 31/35/37/39
code=$1; tag=$2
cd $code
for s in 31 35 37 39; do case $s in 31) t=/tmp/s4data/lead/t1_31;; 35) t=/tmp/s6data/lead/t1_35;; 37) t=/tmp/s7data/haze/t1_37;; 39) t=/tmp/s7data/haze/t1_39;; esac
for p in ${SRCS:-semantic gt}; do PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s10data/semflip/capfit.py $t /tmp/s10data/semflip/cap_${tag}${s}_$p.pt $p > /tmp/s10data/semflip/cap_${tag}${s}_$p.log 2>&1; echo "done $s $p"; done; done
