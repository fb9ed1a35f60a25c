#!/usr/bin/env bash
# Semantic branch (experiment=demo_short) on the demo's own data (seed 0), 40 steps (2 epochs of 20), with 1 and 2
# torch threads, alternating 1,2,1,2 (paired by position), each run alone under `nice -n 5`; wall and CPU by
# /usr/bin/time, the load average before and after each. Usage: threads_ab.sh DATA OUT [ORDER...]
set -euo pipefail
DATA=$1; OUT=$2; shift 2
ORDER=${*:-1 2 1 2}
ROOT=$(cd "$(dirname "$0")/../../../../.." && pwd)
mkdir -p "$OUT"
i=0
for t in $ORDER; do
  i=$((i + 1)); run="$OUT/r${i}_t${t}"; rm -rf "$run"
  echo "run $i threads $t load_before $(cut -d' ' -f1-3 /proc/loadavg) $(date -u +%T)" >> "$OUT/log.txt"
  OMP_WAIT_POLICY=PASSIVE OMP_NUM_THREADS=$t PYTHONPATH=$ROOT/src:$ROOT nice -n 5 /usr/bin/time -v -o "$run.time" \
    /work/main/.venv/bin/python -m sdn3d.cli.train branch=semantic experiment=demo_short data.root="$DATA" seed=0 \
    threads="$t" datamodule.num_workers=0 hydra.run.dir="$run" trainer.max_epochs=2 \
    trainer.enable_progress_bar=false '~callbacks.progress_bar' > "$run.out" 2>&1
  echo "run $i threads $t load_after $(cut -d' ' -f1-3 /proc/loadavg) $(date -u +%T) wall $(grep Elapsed "$run.time" | awk '{print $NF}') user $(grep 'User time' "$run.time" | awk '{print $NF}') sys $(grep 'System time' "$run.time" | awk '{print $NF}')" >> "$OUT/log.txt"
done
