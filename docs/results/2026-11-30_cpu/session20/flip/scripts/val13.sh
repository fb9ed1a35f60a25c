#!/bin/bash
# val13.sh: pose tables (session 11 template's pose.sh: --part all, 40 frames, 312x96, photo crops, threads 1,
# min-pixels 64, the demo's weights; rows gt_fit and pred_fit) of main (/tmp/s20data/lead/base_4044) and of the
# branch's final code (/tmp/s20data/flip/code_24c2f80) on tuning tree val13 (/tmp/s11data/template/val13), run after
# the code was final (reported, not used to choose anything).
POSE=/work/main/docs/results/2026-11-29_cpu/session11/template/scripts/pose.sh; OUT=/tmp/s20data/flip/val13
for C in main:/tmp/s20data/lead/base_4044 branch:/tmp/s20data/flip/code_24c2f80; do
  BENCH=${C#*:}/benchmarks/pose_table.py bash $POSE ${C#*:} /tmp/s11data/template/val13 $OUT/pose_${C%%:*}.json gt_fit pred_fit \
    > $OUT/pose_${C%%:*}.log 2>&1
  echo "val13 ${C%%:*} rc=$? $(date -u +%T)" >> $OUT/done.log
done
