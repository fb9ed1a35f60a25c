#!/bin/bash
# Run from /tmp/s23data/border/diag (writes its logs there). code_f03 / code_B / code_142: git archives of the named
# commits (code_B: f038932 with the near-end condition removed, the rule of 142ebf0).
# branch f038932 (archive code_f03), w0: 31 then 37 | 35
(bash /work/wt/border/docs/results/2026-11-30_cpu/session23/border/scripts/diag.sh /tmp/s23data/border/code_f03 /tmp/s21data/trees/t1_31 /tmp/s23data/border/diag/br_w0_31 > br_w0_31.log 2>&1; echo "31 $(date -u +%T)"
 bash /work/wt/border/docs/results/2026-11-30_cpu/session23/border/scripts/diag.sh /tmp/s23data/border/code_f03 /tmp/s21data/trees/t1_37 /tmp/s23data/border/diag/br_w0_37 > br_w0_37.log 2>&1; echo "37 $(date -u +%T)") &
(bash /work/wt/border/docs/results/2026-11-30_cpu/session23/border/scripts/diag.sh /tmp/s23data/border/code_f03 /tmp/s21data/trees/t1_35 /tmp/s23data/border/diag/br_w0_35 > br_w0_35.log 2>&1; echo "35 $(date -u +%T)") &
wait
