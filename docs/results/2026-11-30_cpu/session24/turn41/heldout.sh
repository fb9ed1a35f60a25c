#!/bin/bash
# heldout.sh SOURCE: the held-out tree 2229 (gen_cf.py /tmp/s24data/turn41/cf2229 2229 0006,0018,0020 6, main's
# generator) measured once with probe.sh, main 279f996 (/tmp/s24data/lead/base_279) then the branch's final code
# (/tmp/s24data/turn41/br_final, a git archive of 798e6ed), source scene SOURCE (oracle or semantic); outputs under
# /tmp/s24data/turn41/bench/ho_{main,branch}_cf2229_SOURCE. Run one per source, both at once; then turns.py.
HERE=$(cd "$(dirname "$0")" && pwd)
T=/tmp/s24data/turn41/cf2229; B=/tmp/s24data/turn41/bench
bash "$HERE/probe.sh" /tmp/s24data/lead/base_279 $T $B/ho_main_cf2229_$1 $1
bash "$HERE/probe.sh" /tmp/s24data/turn41/br_final $T $B/ho_branch_cf2229_$1 $1
