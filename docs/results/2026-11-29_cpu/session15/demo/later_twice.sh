#!/usr/bin/env bash
# threads_later determinism: the semantic training (experiment=demo_short, the demo's data, seed 0) for 2 epochs of 5
# steps, 1 torch thread for the first epoch and 2 from the second (threads=1 threads_later={after_epochs:1,threads:2},
# OMP_NUM_THREADS=1 as the demo's lane gives it), twice; then same_weights.py on the two runs.
# Usage: later_twice.sh DATA OUT
set -euo pipefail
DATA=$1; OUT=$2
HERE=$(cd "$(dirname "$0")" && pwd); ROOT=$(cd "$HERE/../../../../.." && pwd)
mkdir -p "$OUT"
export OMP_WAIT_POLICY=PASSIVE OMP_NUM_THREADS=1 PYTHONPATH=$ROOT/src:$ROOT
for run in a b; do
  rm -rf "$OUT/$run"
  echo "run $run load $(cut -d' ' -f1-3 /proc/loadavg) $(date -u +%T)" >> "$OUT/log.txt"
  nice -n 5 /usr/bin/time -v -o "$OUT/$run.time" /work/main/.venv/bin/python -m sdn3d.cli.train branch=semantic \
    experiment=demo_short data.root="$DATA" seed=0 threads=1 'threads_later={after_epochs:1,threads:2}' \
    datamodule.num_workers=0 hydra.run.dir="$OUT/$run" trainer.max_epochs=2 trainer.limit_train_batches=5 \
    trainer.enable_progress_bar=false '~callbacks.progress_bar' > "$OUT/$run.out" 2>&1
  grep -h "threads_later\|epoch .* done" "$OUT/$run.out" | cut -c1-160 >> "$OUT/log.txt"
  grep -h "Elapsed\|User time\|System time\|Percent of CPU" "$OUT/$run.time" >> "$OUT/log.txt"
done
/work/main/.venv/bin/python "$HERE/same_weights.py" "$OUT/a" "$OUT/b" >> "$OUT/log.txt"
