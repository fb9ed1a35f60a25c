#!/bin/bash
# lv.sh TAG SEEDS...: lampvar.py on the captures of the given seeds, semantic and gt, per variation
for s in "$@"; do case $s in 31) t=/tmp/s4data/lead/t1_31;; 35) t=/tmp/s6data/lead/t1_35;; 37) t=/tmp/s7data/haze/t1_37;; 39) t=/tmp/s7data/haze/t1_39;; esac
for p in semantic gt; do for v in clone fog rain; do cd /work/wt/semflip && PYTHONPATH=$PWD/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s10data/semflip/lampvar.py $t /tmp/s10data/semflip/cap_${TAG:-m}${s}_$p.pt $v 2>&1 | grep -v "n 0 " | tail -1; done; done; done
