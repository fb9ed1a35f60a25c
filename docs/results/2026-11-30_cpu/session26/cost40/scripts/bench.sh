#!/bin/bash
# bench.sh OUT_PREFIX THREADS [REPEATS]: benchmarks/edit_call.py, the lead's command: this branch (mode "run": a
# frozen archive of the branch, $BRANCH, default /tmp/s26data/cost40/tree_cost40) against main's plain tree
# (/tmp/s26data/lead/base_9fa, mode "main"), calls interleaved, run mode both. Compile both trees first
# (python -m compileall -q src, PYTHONDONTWRITEBYTECODE unset). Writes OUT_PREFIX_t<THREADS>.json and .load.
OUT=$1; TH=$2; REP=${3:-7}; WT=/work/wt/cost40; B=${BRANCH:-/tmp/s26data/cost40/tree_cost40}
cd $WT && uptime > ${OUT}_t${TH}.load
OMP_NUM_THREADS=1 PYTHONPATH=$B/src SDN3D_CONFIG_DIR=$B/conf nice -n 5 /work/main/.venv/bin/python \
  benchmarks/edit_call.py --run /tmp/s21data/demo/out \
  --image /tmp/s21data/trees/t1_31/vkitti_1.3.1_rgb/0001/clone/00000.png \
  --edits docs/results/2026-11-28_cpu/session4/cost/spec31.yaml --size 624 192 --threads $TH --repeats $REP \
  --modes run --tree main=/tmp/s26data/lead/base_9fa --tree-mode run --out ${OUT}_t${TH}.json > /dev/null
echo "rc=$?" >> ${OUT}_t${TH}.load; uptime >> ${OUT}_t${TH}.load
