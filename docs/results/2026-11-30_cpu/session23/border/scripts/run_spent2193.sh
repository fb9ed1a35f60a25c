#!/bin/bash
# Run from /tmp/s23data/border/diag (logs there); code_142: git archive of 142ebf0.
# spent held-out 2193 (session 21's), w0, after this session's held-out (chooses nothing): main | branch
(bash /work/wt/border/docs/results/2026-11-30_cpu/session23/border/scripts/diag.sh /tmp/s23data/lead/base_73c /tmp/s21data/trees/t1_2193 /tmp/s23data/border/diag/main_w0_2193 > main_w0_2193.log 2>&1; echo "main $(date -u +%T)") &
(bash /work/wt/border/docs/results/2026-11-30_cpu/session23/border/scripts/diag.sh /tmp/s23data/border/code_142 /tmp/s21data/trees/t1_2193 /tmp/s23data/border/diag/br_w0_2193 > br_w0_2193.log 2>&1; echo "branch $(date -u +%T)") &
wait
