#!/usr/bin/env bash
# Where one semantic training epoch's wall goes (experiment=demo_short on the demo's data, seed 0, 1 thread,
# 1 epoch = 20 steps, then the test): Lightning's simple profiler (per hook: data fetch, training_step, backward,
# optimizer step, checkpoint saving, logging) and, for op-level detail, cProfile of the same run.
# Usage: profile_step.sh DATA OUT
set -euo pipefail
DATA=$1; OUT=$2
ROOT=$(cd "$(dirname "$0")/../../../../.." && pwd)
mkdir -p "$OUT"; rm -rf "$OUT/simple" "$OUT/cprof"
common=(branch=semantic experiment=demo_short data.root="$DATA" seed=0 threads=1 datamodule.num_workers=0
        trainer.max_epochs=1 trainer.enable_progress_bar=false '~callbacks.progress_bar')
export OMP_WAIT_POLICY=PASSIVE OMP_NUM_THREADS=1 PYTHONPATH=$ROOT/src:$ROOT
nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.train "${common[@]}" hydra.run.dir="$OUT/simple" \
  +trainer.profiler=simple > "$OUT/simple.out" 2>&1
nice -n 5 /work/main/.venv/bin/python -m cProfile -o "$OUT/cprof.pstats" -m sdn3d.cli.train "${common[@]}" \
  hydra.run.dir="$OUT/cprof" > "$OUT/cprof.out" 2>&1
/work/main/.venv/bin/python -c "
import pstats, sys
p = pstats.Stats('$OUT/cprof.pstats', stream=open('$OUT/cprof_top.txt', 'w'))
p.sort_stats('tottime').print_stats(45)
p.sort_stats('cumulative').print_stats(70)
"
