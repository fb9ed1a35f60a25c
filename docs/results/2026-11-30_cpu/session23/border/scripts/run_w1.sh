#!/bin/bash
# Run from /tmp/s23data/border/diag (writes its logs there). code_f03 / code_B / code_142: git archives of the named
# commits (code_B: f038932 with the near-end condition removed, the rule of 142ebf0).
# w1 (second demo training), trees 31 then 37: main (base_73c) | branch (code_142 = 142ebf0)
export RUNS=/tmp/s21data/demo1/out/runs
(for t in 31 37; do bash /work/wt/border/docs/results/2026-11-30_cpu/session23/border/scripts/diag.sh /tmp/s23data/lead/base_73c /tmp/s21data/trees/t1_$t /tmp/s23data/border/diag/main_w1_$t > main_w1_$t.log 2>&1; echo "main $t $(date -u +%T)"; done) &
(for t in 31 37; do bash /work/wt/border/docs/results/2026-11-30_cpu/session23/border/scripts/diag.sh /tmp/s23data/border/code_142 /tmp/s21data/trees/t1_$t /tmp/s23data/border/diag/br_w1_$t > br_w1_$t.log 2>&1; echo "branch $t $(date -u +%T)"; done) &
wait
