#!/bin/bash
# heldout.sh: the held-out measurement, once: main (1e29128, /tmp/s22data/lead/base_1e2) and the branch's final code
# (git archive 13440f4 at /tmp/s22data/side2/br_final) on the counterfactual tree of seed 2207
# (/tmp/s22data/side2/trees/cf2207), turns, fill rays, ground-truth geometry (oracle) then predicted (session 21's
# demo weights w0), main and branch two at a time (bench.sh: threads 1, nice 5). Out: /tmp/s22data/side2/bench/.
H=$(cd "$(dirname "$0")" && pwd); T=/tmp/s22data/side2/trees/cf2207; O=/tmp/s22data/side2/bench
W=/tmp/s22data/side2/br_final; rm -rf $W; mkdir -p $W $O; (cd /work/wt/side2 && git archive 13440f4 | tar -x -C $W)
for s in oracle semantic; do
  bash "$H/bench.sh" /tmp/s22data/lead/base_1e2 $T "$O/main_cf2207_$s" $s "[rays]" "[turn]" &
  bash "$H/bench.sh" $W $T "$O/branch_cf2207_$s" $s "[rays]" "[turn]" &
  wait
done
