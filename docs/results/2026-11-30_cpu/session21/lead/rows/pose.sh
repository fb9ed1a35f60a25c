#!/bin/bash
while ! grep -q "^all" /tmp/s21data/lead/robust.log 2>/dev/null; do sleep 15; done
cd /work/main
RUNS=/tmp/s21data/demo/out/runs BENCH=/tmp/s21data/lead/code_9ed55bc/benchmarks/pose_table.py bash docs/results/2026-11-29_cpu/session11/template/scripts/pose.sh /tmp/s21data/lead/code_9ed55bc /tmp/s21data/trees/t1_2193 /tmp/s21data/lead/pose2193_w0.json gt_branch gt_fit pred_fit > /tmp/s21data/lead/pose2193_w0.log 2>&1
echo "pose w0 rc=$? $(date -u +%T)" >> /tmp/s21data/lead/robust.log
